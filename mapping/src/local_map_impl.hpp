#pragma once
// Internal: the local map's storage and its lazily built PCL search structures. Included only by
// the mapping TUs that need PCL (local_map.cpp, registration.cpp), never by a public header.

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

#include <Eigen/Core>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "dorado/mapping/local_map.hpp"

namespace dorado::mapping {

struct VoxelKey {
    int64_t x, y, z;
    bool operator==(const VoxelKey &o) const { return x == o.x && y == o.y && z == o.z; }
};

struct VoxelKeyHash {
    std::size_t operator()(const VoxelKey &k) const {
        // The spatial hash of Teschner et al. (2003), as in kiss-icp's voxel map.
        return static_cast<std::size_t>((k.x * 73856093) ^ (k.y * 19349669) ^ (k.z * 83492791));
    }
};

struct LocalMap::Impl {
    LocalMapConfig config;
    std::unordered_map<VoxelKey, std::vector<Eigen::Vector3d>, VoxelKeyHash> voxels;
    std::size_t point_count = 0;

    // Search structures, rebuilt on first use after an Update. PCL works in float: the cloud is
    // stored relative to `origin_world` (the vehicle at rebuild time) to keep the precision.
    bool dirty = true;
    Eigen::Vector3d origin_world = Eigen::Vector3d::Zero();
    std::vector<Eigen::Vector3d> points_world;  // same order as the cloud
    pcl::PointCloud<pcl::PointXYZ>::Ptr cloud{new pcl::PointCloud<pcl::PointXYZ>};
    pcl::search::KdTree<pcl::PointXYZ>::Ptr tree{new pcl::search::KdTree<pcl::PointXYZ>};
    Eigen::Vector3d last_position_world = Eigen::Vector3d::Zero();

    // Local covariance of each point's k-neighbourhood (unit-free shape, GICP-regularised),
    // computed on demand; `covariance_ready[i]` says whether entry i is valid.
    int covariance_neighbours = 8;
    double plane_flatness = 0.1;
    std::vector<Eigen::Matrix3d> covariances;
    std::vector<Eigen::Vector3d> normals;
    std::vector<uint8_t> covariance_ready;

    VoxelKey KeyOf(const Eigen::Vector3d &p) const;
    /// Rebuilds cloud + kd-tree when the map changed since the last call.
    void EnsureSearch();
    /// Regularised covariance of point i's neighbourhood: V diag(flatness, 1, 1) V^T, where V
    /// are the eigenvectors of the sample covariance (smallest first), i.e. GICP's plane model.
    const Eigen::Matrix3d &Covariance(int i);
    /// Unit normal of point i's neighbourhood (eigenvector of the smallest eigenvalue).
    const Eigen::Vector3d &Normal(int i);
    /// Computes every covariance (for PCL GICP / point-to-plane on the whole map).
    void ComputeAllCovariances();
    /// Sets the neighbourhood model; clears the cache when it changes.
    void SetCovarianceModel(int neighbours, double flatness);
};

}  // namespace dorado::mapping
