#pragma once
/// @file voxel_key.hpp
/// The voxel index of a point, and its hash: one spelling for the local map and the output map.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace dorado::mapping {

/// 32-bit voxel indices keep hash tables small (a search is bound by its cache misses);
/// VoxelKeyOf clamps them well inside the int32 range, so key arithmetic never overflows.
struct VoxelKey {
    int32_t x, y, z;
    bool operator==(const VoxelKey &o) const { return x == o.x && y == o.y && z == o.z; }
};

struct VoxelKeyHash {
    std::size_t operator()(const VoxelKey &k) const {
        // The spatial hash of Teschner et al. (2003), as in kiss-icp's voxel map (unsigned, so
        // the products wrap instead of overflowing).
        return static_cast<std::size_t>((static_cast<uint32_t>(k.x) * 73856093u) ^
                                        (static_cast<uint32_t>(k.y) * 19349669u) ^
                                        (static_cast<uint32_t>(k.z) * 83492791u));
    }
};

/// Voxel index of a coordinate in voxel units (floor), clamped to +-2^30.
inline int32_t VoxelIndex(double s) {
    constexpr double kLimit = 1 << 30;
    return static_cast<int32_t>(std::clamp(std::floor(s), -kLimit, kLimit));
}

inline VoxelKey VoxelKeyOf(const Eigen::Vector3d &p, double voxel_m) {
    const Eigen::Vector3d s = p / voxel_m;
    return {VoxelIndex(s.x()), VoxelIndex(s.y()), VoxelIndex(s.z())};
}

}  // namespace dorado::mapping
