// Supervoxels + LCCP on one cluster (osd_lccp.h). PCL stays in this file.
#include "osd_lccp.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/segmentation/lccp_segmentation.h>
#include <pcl/segmentation/supervoxel_clustering.h>

#include <map>

namespace annex {

std::vector<std::vector<int>> lccp_split(const Frame& f, const std::vector<int>& pixels,
                                         const LccpParams& params) {
  using PointT = pcl::PointXYZRGBA;
  pcl::PointCloud<PointT>::Ptr cloud(new pcl::PointCloud<PointT>);
  for (int i : pixels) {
    PointT p;
    p.x = f.points[i].x;
    p.y = f.points[i].y;
    p.z = f.points[i].z;
    p.r = f.points[i].r;
    p.g = f.points[i].g;
    p.b = f.points[i].b;
    p.a = 255;
    cloud->push_back(p);
  }
  if (cloud->size() < 20) return {pixels};
  pcl::SupervoxelClustering<PointT> super(static_cast<float>(params.voxel_m),
                                          static_cast<float>(params.seed_m));
  super.setUseSingleCameraTransform(false);
  super.setInputCloud(cloud);
  super.setColorImportance(0.0f);
  super.setSpatialImportance(1.0f);
  super.setNormalImportance(4.0f);
  std::map<std::uint32_t, pcl::Supervoxel<PointT>::Ptr> supervoxels;
  super.extract(supervoxels);
  if (supervoxels.empty()) return {pixels};
  std::multimap<std::uint32_t, std::uint32_t> adjacency;
  super.getSupervoxelAdjacency(adjacency);
  pcl::LCCPSegmentation<PointT> lccp;
  lccp.setConcavityToleranceThreshold(static_cast<float>(params.concavity_deg));
  lccp.setSanityCheck(true);
  lccp.setSmoothnessCheck(true, static_cast<float>(params.voxel_m), static_cast<float>(params.seed_m),
                          static_cast<float>(params.smoothness));
  lccp.setKFactor(0);
  lccp.setInputSupervoxels(supervoxels, adjacency);
  lccp.setMinSegmentSize(params.min_segment_supervoxels);
  lccp.segment();
  pcl::PointCloud<pcl::PointXYZL>::Ptr labels = super.getLabeledCloud();
  lccp.relabelCloud(*labels);
  std::map<std::uint32_t, std::vector<int>> groups;
  for (size_t k = 0; k < labels->size(); ++k) groups[(*labels)[k].label].push_back(pixels[k]);
  std::vector<std::vector<int>> out;
  for (auto& [label, g] : groups)
    if (label != 0) out.push_back(std::move(g));
  return out;
}

}  // namespace annex
