#pragma once
// Internal: the local map's storage (an incremental voxel hash) and its search. Included only by
// the mapping TUs that need it (local_map.cpp, registration.cpp, association.cpp), never by a
// public header.
//
// Why not a PCL k-d tree: the map changed on every keyframe, so the tree was rebuilt (p95 32 ms
// per scan on a 2 000-point seq04 drive), and FLANN enters an OpenMP region on every single
// query (half of the mapper's CPU time went to libgomp and futex calls). The voxel hash is
// updated in place and answers "nearest point within d" exactly by visiting only the voxels whose
// box is closer than the best distance so far.

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <tsl/robin_map.h>

#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

#include "dorado/mapping/local_map.hpp"
#include "dorado/mapping/voxel_key.hpp"

namespace dorado::mapping {

/// A map point's local shape is fitted to its k nearest map points (as a k-d tree would give),
/// searched in growing shells of voxels around it; the search stops at kShapeReachM (and at most
/// kMaxShapeRings voxels, Chebyshev distance of the keys), so a shape depends on a bounded
/// neighbourhood and a map update changes only the cached shapes near it.
inline constexpr double kShapeReachM = 6.0;
inline constexpr int kMaxShapeRings = 16;
/// Edge, in voxels, of the blocks that record when the map last changed in them: a shape is
/// stale when a block its neighbourhood overlaps changed after it was fitted.
inline constexpr int kBlockVoxels = 5;

/// The nearest-point search looks at most this many voxels away (a bound on its cost when a
/// caller passes a huge distance).
inline constexpr int kMaxSearchRings = 16;

struct LocalMap::Impl {
    LocalMapConfig config;

    // Storage: voxel v owns the slots [first, first + max_points_per_voxel) of the pools below;
    // a slot keeps its index while its voxel lives, so cached shapes and match indices stay valid
    // across updates. Freed blocks are reused.
    struct Voxel {
        int32_t first = 0;
        int32_t count = 0;
    };
    tsl::robin_map<VoxelKey, Voxel, VoxelKeyHash> voxels;
    std::vector<Eigen::Vector3d> points_world;  ///< slot pool (free slots hold stale values)
    std::vector<int32_t> free_blocks;
    std::size_t point_count = 0;
    uint32_t update_stamp = 0;                                ///< Update calls so far
    tsl::robin_map<VoxelKey, uint32_t, VoxelKeyHash> blocks;  ///< block -> last change

    // PCL works in float: its copy of the slot pool is stored relative to `origin_world` (the
    // vehicle at the last update, rounded) to keep the precision; rebuilt lazily (a copy, no tree).
    bool cloud_dirty = true;
    Eigen::Vector3d origin_world = Eigen::Vector3d::Zero();
    Eigen::Vector3d last_position_world = Eigen::Vector3d::Zero();
    pcl::PointCloud<pcl::PointXYZ>::Ptr cloud{new pcl::PointCloud<pcl::PointXYZ>};

    // Local shape of each slot's neighbourhood (unit-free, GICP-regularised), computed on demand
    // and cached until the map changes near it: `fitted_at[s]` is the update after which slot s's
    // shape was fitted (0: never). Allocated on the first request, so that a map nobody registers
    // against (the whole-run output map) stores its points only.
    bool shapes_used = false;
    int covariance_neighbours = 8;
    double plane_flatness = 0.1;
    std::vector<Eigen::Matrix3d> covariances;
    std::vector<Eigen::Vector3d> normals;
    std::vector<uint32_t> fitted_at;
    std::vector<uint8_t> fitted_rings;  ///< the neighbourhood's reach, in voxels
    mutable std::vector<std::pair<double, int32_t>> scratch;  ///< k-NN candidates

    [[nodiscard]] VoxelKey KeyOf(const Eigen::Vector3d &p) const;
    /// Adds p to its voxel when the voxel has room; returns whether it did.
    bool Insert(const Eigen::Vector3d &p);
    /// Drops the voxels whose first point is farther than max_distance_m from position_world.
    void Crop(const Eigen::Vector3d &position_world);
    /// Sizes the shape caches to the slot pool.
    void ResizeShapes();
    /// Allocates the shape caches on the first request for a shape.
    void UseShapes();
    /// Shells searched at most for a shape: kShapeReachM in voxels, capped at kMaxShapeRings.
    [[nodiscard]] int MaxShapeRings() const;
    /// Records that voxel `key` changed in this update (its block's stamp).
    void MarkChanged(const VoxelKey &key);
    /// Whether slot i's cached shape is still that of its neighbourhood.
    [[nodiscard]] bool ShapeIsCurrent(int32_t i) const;

    /// Nearest map point to query_world closer than max_distance_m (exact; the distance is capped
    /// at kMaxSearchRings voxels), or index -1.
    [[nodiscard]] Neighbour Nearest(const Eigen::Vector3d &query_world,
                                    double max_distance_m) const;
    /// The k nearest map points to slot i (itself included; exact unless they reach beyond
    /// MaxShapeRings() voxels, then the k nearest within them), into `scratch` as (squared
    /// distance, slot) in no particular order. Returns the reach searched, in voxels.
    int NearestInNeighbourhood(int32_t i, int k) const;

    /// Rebuilds PCL's float copy of the slot pool when the map changed since the last call.
    void EnsureCloud();
    /// Regularised covariance of slot i's neighbourhood: V diag(flatness, 1, 1) V^T, where V
    /// are the eigenvectors of the sample covariance (smallest first), i.e. GICP's plane model.
    const Eigen::Matrix3d &Covariance(int32_t i);
    /// Unit normal of slot i's neighbourhood (eigenvector of the smallest eigenvalue).
    const Eigen::Vector3d &Normal(int32_t i);
    /// Computes every live slot's covariance (for PCL GICP / point-to-plane on the whole map).
    void ComputeAllCovariances();
    /// Sets the neighbourhood model; clears the cache when it changes.
    void SetCovarianceModel(int neighbours, double flatness);
    /// Calls f(slot) for every live slot.
    template <typename F>
    void ForEachSlot(F &&f) const {
        for (const auto &[key, voxel] : voxels)
            for (int32_t s = voxel.first; s < voxel.first + voxel.count; ++s) f(s);
    }
};

}  // namespace dorado::mapping
