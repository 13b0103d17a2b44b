// The paper's pipeline built from PCL 1.13's stock filters, as a baseline for the
// benchmark: 5 mm voxel grid, SAC plane (perpendicular to up), projected convex hull,
// polygonal prism, Euclidean clusters, MLS with normals, then SAC sphere, cylinder and
// cone fits per cluster where the most inliers win (the decision FIELD-NOTES warns
// about). Kept deliberately straightforward.
#include <pcl/ModelCoefficients.h>
#include <pcl/common/common.h>
#include <pcl/filters/extract_indices.h>
#include <pcl/filters/project_inliers.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>
#include <pcl/segmentation/extract_polygonal_prism_data.h>
#include <pcl/segmentation/sac_segmentation.h>
#include <pcl/surface/convex_hull.h>
#include <pcl/surface/mls.h>

#include <chrono>
#include <cmath>

#include "annex/reference/scanner_pcl_reference.h"

namespace annex {
namespace {

using Clock = std::chrono::steady_clock;
using Cloud = pcl::PointCloud<pcl::PointXYZ>;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

Vec3 v3(const pcl::PointXYZ& p) { return {p.x, p.y, p.z}; }

}  // namespace

Result<ScanResult> scan_frame_pcl_reference(const Frame& frame, const PclReferenceParams& params) {
  const Location where{"frame " + std::to_string(frame.index), 0, 0};
  ScanResult result;
  auto t0 = Clock::now();
  Cloud::Ptr cloud(new Cloud);
  cloud->reserve(frame.points.size());
  for (const PointXYZRGB& p : frame.points)
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && p.z > 0)
      cloud->push_back({p.x, p.y, p.z});
  if (cloud->size() < 100) return Error{"the frame has no valid depth points", where};
  Cloud::Ptr voxel(new Cloud);
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setInputCloud(cloud);
  grid.setLeafSize(params.voxel_m, params.voxel_m, params.voxel_m);
  grid.filter(*voxel);
  result.stages.push_back({"voxel", ms_since(t0)});

  t0 = Clock::now();
  pcl::ModelCoefficients::Ptr coeff(new pcl::ModelCoefficients);
  pcl::PointIndices::Ptr inliers(new pcl::PointIndices);
  pcl::SACSegmentation<pcl::PointXYZ> seg;
  seg.setOptimizeCoefficients(true);
  seg.setModelType(pcl::SACMODEL_PERPENDICULAR_PLANE);
  seg.setAxis(Eigen::Vector3f(0, -1, 0));
  seg.setEpsAngle(40.0 * M_PI / 180.0);
  seg.setMethodType(pcl::SAC_RANSAC);
  seg.setDistanceThreshold(params.plane_distance_m);
  seg.setMaxIterations(1000);
  seg.setInputCloud(voxel);
  seg.segment(*inliers, *coeff);
  if (inliers->indices.size() < 100 || coeff->values.size() != 4)
    return Error{"no horizontal plane found", where};
  Vec3 n{coeff->values[0], coeff->values[1], coeff->values[2]};
  double d = coeff->values[3];
  if (n.y > 0) {
    n = n * -1.0;
    d = -d;
  }
  result.plane = {n, d};
  result.scene.support = result.plane;
  result.plane_inliers = static_cast<int>(inliers->indices.size());
  result.stages.push_back({"plane", ms_since(t0)});

  t0 = Clock::now();
  Cloud::Ptr projected(new Cloud), hull(new Cloud);
  pcl::ProjectInliers<pcl::PointXYZ> proj;
  proj.setModelType(pcl::SACMODEL_PLANE);
  proj.setInputCloud(voxel);
  proj.setIndices(inliers);
  proj.setModelCoefficients(coeff);
  proj.filter(*projected);
  pcl::ConvexHull<pcl::PointXYZ> chull;
  chull.setInputCloud(projected);
  chull.setDimension(2);
  chull.reconstruct(*hull);
  pcl::PointIndices::Ptr above(new pcl::PointIndices);
  pcl::ExtractPolygonalPrismData<pcl::PointXYZ> prism;
  prism.setInputCloud(voxel);
  prism.setInputPlanarHull(hull);
  prism.setHeightLimits(0.012, 0.6);
  prism.segment(*above);
  // Bound by distance to our plane as well (the prism refits its own plane).
  Cloud::Ptr objects(new Cloud);
  for (int i : above->indices) {
    const double h = dot(n, v3((*voxel)[i])) + d;
    if (h > 0.012 && h < 0.6) objects->push_back((*voxel)[i]);
  }
  for (const auto& p : *hull) result.hull.push_back(v3(p));
  result.stages.push_back({"prism", ms_since(t0)});

  t0 = Clock::now();
  std::vector<pcl::PointIndices> cluster_indices;
  if (!objects->empty()) {
    pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
    tree->setInputCloud(objects);
    pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
    ec.setClusterTolerance(params.cluster_tolerance_m);
    ec.setMinClusterSize(params.min_cluster_points);
    ec.setMaxClusterSize(1000000);
    ec.setSearchMethod(tree);
    ec.setInputCloud(objects);
    ec.extract(cluster_indices);
  }
  result.stages.push_back({"clusters", ms_since(t0)});

  t0 = Clock::now();
  std::vector<pcl::PointCloud<pcl::PointNormal>::Ptr> smoothed;
  for (const pcl::PointIndices& ci : cluster_indices) {
    Cloud::Ptr c(new Cloud);
    for (int i : ci.indices) c->push_back((*objects)[i]);
    pcl::PointCloud<pcl::PointNormal>::Ptr out(new pcl::PointCloud<pcl::PointNormal>);
    pcl::MovingLeastSquares<pcl::PointXYZ, pcl::PointNormal> mls;
    pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
    mls.setComputeNormals(true);
    mls.setInputCloud(c);
    mls.setPolynomialOrder(2);
    mls.setSearchMethod(tree);
    mls.setSearchRadius(params.mls_radius_m);
    mls.process(*out);
    smoothed.push_back(out);
  }
  result.stages.push_back({"mls", ms_since(t0)});

  t0 = Clock::now();
  for (const auto& c : smoothed) {
    ScanCluster sc;
    pcl::PointCloud<pcl::Normal>::Ptr normals(new pcl::PointCloud<pcl::Normal>);
    Cloud::Ptr xyz(new Cloud);
    for (const auto& p : *c) {
      xyz->push_back({p.x, p.y, p.z});
      normals->push_back(pcl::Normal(p.normal_x, p.normal_y, p.normal_z));
      sc.points.push_back({p.x, p.y, p.z});
    }
    PhysicalObject obj;
    obj.point_count = static_cast<int>(c->size());
    size_t best = 0;
    for (const auto model : {pcl::SACMODEL_SPHERE, pcl::SACMODEL_CYLINDER, pcl::SACMODEL_CONE}) {
      pcl::SACSegmentationFromNormals<pcl::PointXYZ, pcl::Normal> s;
      s.setModelType(model);
      s.setMethodType(pcl::SAC_RANSAC);
      s.setNormalDistanceWeight(0.1);
      s.setMaxIterations(params.shape_iterations);
      s.setDistanceThreshold(params.shape_distance_m);
      s.setRadiusLimits(0.005, 0.5);
      s.setInputCloud(xyz);
      s.setInputNormals(normals);
      pcl::ModelCoefficients mc;
      pcl::PointIndices in;
      s.segment(in, mc);
      if (in.indices.size() <= best) continue;
      best = in.indices.size();
      PhysicalPrimitive p;
      const auto& v = mc.values;
      if (model == pcl::SACMODEL_SPHERE && v.size() == 4) {
        p.kind = ShapeKind::sphere;
        p.center = {v[0], v[1], v[2]};
        p.dimensions_m = {std::abs(v[3])};
      } else if (model == pcl::SACMODEL_CYLINDER && v.size() == 7) {
        const Vec3 o{v[0], v[1], v[2]};
        const Vec3 a = normalized(Vec3{v[3], v[4], v[5]});
        double lo = 1e18, hi = -1e18;
        for (int i : in.indices) {
          const double t = dot(v3((*xyz)[i]) - o, a);
          lo = std::min(lo, t);
          hi = std::max(hi, t);
        }
        p.kind = ShapeKind::cylinder;
        p.dimensions_m = {std::abs(v[6]), hi - lo};
        p.center = o + a * ((lo + hi) / 2);
        p.axis = a;
      } else if (model == pcl::SACMODEL_CONE && v.size() == 7) {
        const Vec3 apex{v[0], v[1], v[2]};
        const Vec3 a = normalized(Vec3{v[3], v[4], v[5]});
        double hi = 0;
        for (int i : in.indices) hi = std::max(hi, dot(v3((*xyz)[i]) - apex, a));
        p.kind = ShapeKind::cone;
        p.dimensions_m = {hi * std::tan(v[6]), hi};
        p.center = apex + a * (hi / 2);
        p.axis = a * -1.0;
      } else {
        continue;
      }
      p.fit = static_cast<double>(in.indices.size()) / std::max<size_t>(1, c->size());
      obj.primitives = {p};
      obj.fit = p.fit;
    }
    result.scene.objects.push_back(obj);
    result.clusters.push_back(std::move(sc));
  }
  result.stages.push_back({"shapes", ms_since(t0)});
  order_and_name_objects(result);
  return result;
}

}  // namespace annex
