#pragma once
/// @file local_map.hpp
/// The local map the scans are registered against: points in the world frame, kept in a voxel
/// hash (at most a few points per voxel, kiss-icp style) and cropped to a radius around the
/// vehicle. The hash is updated in place (no k-d tree to rebuild) and is also the search
/// structure: nearest point within a distance, and the local shapes of the map's neighbourhoods,
/// cached until the map changes near them. Its memory is bounded by the crop radius.

#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <vector>

#include "dorado/mapping/voxel_key.hpp"

namespace dorado::mapping {

struct LocalMapConfig {
    double voxel_size_m = 1.0;     ///< edge of the voxels that bound the map density
    int max_points_per_voxel = 2;  ///< points kept per voxel (the first ones that arrive)
    double max_distance_m =
        80.0;  ///< voxels farther than this from the vehicle are dropped (infinity: never)

    /// Throws std::invalid_argument naming the first bad key.
    void Validate() const;
};

class LocalMap {
  public:
    explicit LocalMap(const LocalMapConfig &config = {});
    ~LocalMap();
    LocalMap(LocalMap &&) noexcept;
    LocalMap &operator=(LocalMap &&) noexcept;

    /// Adds points (world frame) to the voxels that still have room, then drops the voxels farther
    /// than max_distance_m from position_world (the vehicle). Returns the points it added that are
    /// in the map after the update (world frame, in input order).
    Eigen::Matrix3Xd Update(const Eigen::Matrix3Xd &points_world,
                            const Eigen::Vector3d &position_world);

    /// Drops the voxels with these keys (cells of voxel_size_m) and their points: what was seen
    /// moving there (movers.hpp). Returns the number of points dropped.
    std::size_t Remove(const std::vector<VoxelKey> &keys);

    /// Builds PCL's float copy of the map now (otherwise on the first registration after an
    /// Update).
    void BuildIndex() const;

    /// Every map point, in the world frame.
    [[nodiscard]] Eigen::Matrix3Xd Points() const;
    [[nodiscard]] std::size_t size() const;
    [[nodiscard]] bool empty() const { return size() == 0; }
    /// Occupied voxels, and point slots allocated (live points plus free room in the voxels and
    /// freed blocks kept for reuse): the map's memory is proportional to the latter.
    [[nodiscard]] std::size_t voxel_count() const;
    [[nodiscard]] std::size_t capacity() const;
    [[nodiscard]] const LocalMapConfig &config() const;

    /// Nearest map point to query_world closer than max_distance_m (exact; the search reaches at
    /// most 16 voxels): its slot index, stable while its voxel stays in the map, and the squared
    /// distance; index -1 when there is none (and for a distance that is not finite and > 0).
    struct Neighbour {
        int index = -1;
        double distance_squared = 0.0;
    };
    [[nodiscard]] Neighbour Nearest(const Eigen::Vector3d &query_world,
                                    double max_distance_m) const;

    /// Implementation (voxel hash, PCL's float copy); defined in mapping/src/local_map_impl.hpp.
    struct Impl;
    [[nodiscard]] Impl &impl() const { return *impl_; }

  private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace dorado::mapping
