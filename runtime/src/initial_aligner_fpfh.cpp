// InitialAligner fallback: FPFH descriptors (PCL) and our own prerejective RANSAC.
// PCL's SampleConsensusPrerejective draws from the global rand() and never stops
// early (FIELD-NOTES: 2-3 s at 5,000 iterations); this loop is seeded, rejects
// samples by the same 0.9 edge-length similarity and stops once enough of the model
// is explained. The only translation unit with PCL features: compile time.
#include <pcl/features/fpfh.h>
#include <pcl/features/normal_3d.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <tuple>

#include "annex/runtime/initial_aligner.h"

namespace annex {
namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

// One point per occupied voxel (the first seen), so both clouds have similar density.
Cloud::Ptr voxelize(const std::vector<Vec3>& pts, double voxel_m) {
  std::map<std::tuple<long, long, long>, Vec3> cells;
  for (const Vec3& p : pts)
    cells.emplace(std::make_tuple(std::lround(p.x / voxel_m), std::lround(p.y / voxel_m),
                                  std::lround(p.z / voxel_m)),
                  p);
  auto cloud = std::make_shared<Cloud>();
  for (const auto& [key, p] : cells)
    cloud->push_back(
        pcl::PointXYZ(static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)));
  return cloud;
}

pcl::PointCloud<pcl::FPFHSignature33>::Ptr features(const Cloud::Ptr& cloud,
                                                    const FpfhParams& params) {
  auto tree = std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
  auto normals = std::make_shared<pcl::PointCloud<pcl::Normal>>();
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
  ne.setInputCloud(cloud);
  ne.setSearchMethod(tree);
  ne.setRadiusSearch(params.normal_radius_m);
  ne.setViewPoint(0, 0, 0);
  ne.compute(*normals);
  auto out = std::make_shared<pcl::PointCloud<pcl::FPFHSignature33>>();
  pcl::FPFHEstimation<pcl::PointXYZ, pcl::Normal, pcl::FPFHSignature33> fe;
  fe.setInputCloud(cloud);
  fe.setInputNormals(normals);
  fe.setSearchMethod(tree);
  fe.setRadiusSearch(params.feature_radius_m);
  fe.compute(*out);
  return out;
}

bool finite(const pcl::FPFHSignature33& f) {
  return std::all_of(std::begin(f.histogram), std::end(f.histogram),
                     [](float v) { return std::isfinite(v); });
}

Eigen::Vector3d ev(const pcl::PointXYZ& p) {
  return {p.x, p.y, p.z};
}

}  // namespace

std::optional<Pose> align_fpfh(const TrackingModel& model, const TargetCloud& target,
                               const FpfhParams& params) {
  const Cloud::Ptr src = voxelize(model.points, params.voxel_m);
  const Cloud::Ptr dst = voxelize(target.points, params.voxel_m);
  if (src->size() < 10 || dst->size() < 10) return std::nullopt;
  const auto fs = features(src, params);
  const auto fd = features(dst, params);

  // The k most similar target descriptors of every model point.
  auto valid_dst = std::make_shared<pcl::PointCloud<pcl::FPFHSignature33>>();
  std::vector<int> dst_index;
  for (size_t i = 0; i < fd->size(); ++i)
    if (finite((*fd)[i])) {
      valid_dst->push_back((*fd)[i]);
      dst_index.push_back(static_cast<int>(i));
    }
  if (valid_dst->size() < 10) return std::nullopt;
  pcl::KdTreeFLANN<pcl::FPFHSignature33> ftree;
  ftree.setInputCloud(valid_dst);
  const int k = std::max(1, params.correspondence_randomness);
  std::vector<std::vector<int>> similar(src->size());
  std::vector<int> usable;
  std::vector<float> d2(k);
  for (size_t i = 0; i < src->size(); ++i) {
    if (!finite((*fs)[i])) continue;
    pcl::Indices nn(k);
    if (ftree.nearestKSearch((*fs)[i], k, nn, d2) <= 0) continue;
    for (int j : nn) similar[i].push_back(dst_index[j]);
    usable.push_back(static_cast<int>(i));
  }
  if (usable.size() < 3) return std::nullopt;

  pcl::KdTreeFLANN<pcl::PointXYZ> dtree;
  dtree.setInputCloud(dst);
  const double inlier_d = 2.5 * params.voxel_m;
  std::mt19937_64 rng(params.seed);
  std::uniform_int_distribution<size_t> pick(0, usable.size() - 1);
  std::uniform_int_distribution<int> pick_k(0, k - 1);
  Eigen::Matrix4d best = Eigen::Matrix4d::Identity();
  double best_score = -1;
  pcl::Indices nn(1);
  std::vector<float> nd(1);
  for (int it = 0; it < params.max_iterations; ++it) {
    Eigen::Matrix3d a, b;
    for (int s = 0; s < 3; ++s) {
      const int i = usable[pick(rng)];
      const auto& cand = similar[i];
      const int j = cand[static_cast<size_t>(pick_k(rng)) % cand.size()];
      a.col(s) = ev((*src)[i]);
      b.col(s) = ev((*dst)[j]);
    }
    // Prerejection: the triangle's edges must agree within the similarity threshold.
    bool similar_edges = true;
    for (int s = 0; s < 3 && similar_edges; ++s) {
      const double la = (a.col(s) - a.col((s + 1) % 3)).norm();
      const double lb = (b.col(s) - b.col((s + 1) % 3)).norm();
      if (la < 1e-3 || lb < 1e-3 || std::min(la, lb) / std::max(la, lb) < params.similarity)
        similar_edges = false;
    }
    if (!similar_edges) continue;
    const Eigen::Matrix4d tf = Eigen::umeyama(a, b, false);
    int inliers = 0;
    double err = 0;
    for (const auto& p : *src) {
      const Eigen::Vector3d q = tf.topLeftCorner<3, 3>() * ev(p) + tf.topRightCorner<3, 1>();
      const pcl::PointXYZ pq(static_cast<float>(q.x()), static_cast<float>(q.y()),
                             static_cast<float>(q.z()));
      if (dtree.nearestKSearch(pq, 1, nn, nd) > 0 && nd[0] < inlier_d * inlier_d) {
        ++inliers;
        err += nd[0];
      }
    }
    const double fraction = static_cast<double>(inliers) / static_cast<double>(src->size());
    const double score = fraction - 1e-3 * (inliers ? std::sqrt(err / inliers) / inlier_d : 1);
    if (score > best_score) {
      best_score = score;
      best = tf;
    }
    if (fraction >= 0.8) break;  // good enough: stop early
  }
  if (best_score < params.inlier_fraction) return std::nullopt;
  const Eigen::Matrix3d r = best.topLeftCorner<3, 3>();
  Eigen::Quaterniond q(r);
  q.normalize();
  return Pose{{best(0, 3), best(1, 3), best(2, 3)}, {q.w(), q.x(), q.y(), q.z()}};
}

}  // namespace annex
