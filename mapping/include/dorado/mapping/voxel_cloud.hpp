#pragma once
/// @file voxel_cloud.hpp
/// The whole run's map as it is written out (map.pcd, map.ply, map.png): world points thinned to
/// the first one per voxel, unbounded, stored compactly. Unlike LocalMap it has no search, no
/// crop and no shapes: about 40-70 bytes per point (a hash set of voxel keys and float offsets
/// from the first point, 0.5 mm resolution 10 km away), against ~100 for a LocalMap.

#include <Eigen/Core>
#include <cstddef>
#include <memory>

namespace dorado::mapping {

class VoxelCloud {
  public:
    explicit VoxelCloud(double voxel_m);
    ~VoxelCloud();
    VoxelCloud(VoxelCloud &&) noexcept;
    VoxelCloud &operator=(VoxelCloud &&) noexcept;

    /// Keeps each finite point whose voxel is still empty.
    void Add(const Eigen::Matrix3Xd &points_world);

    [[nodiscard]] std::size_t size() const;
    /// Every point, world frame, in the order they were kept.
    [[nodiscard]] Eigen::Matrix3Xd Points() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace dorado::mapping
