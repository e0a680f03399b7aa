#pragma once
/// @file movers.hpp
/// What the mapper keeps out of its map besides the Doppler mask's moving points. The mask flags a
/// point only when its radial velocity disagrees with the static world's: a walker crossing the
/// beam, or the parts of a crowd that move across the line of sight, pass as static. Two rules on
/// what the data already shows catch most of them:
///  - neighbours: a point within `neighbour_radius_m` of a point seen moving in the same scan
///    belongs to the same object (radar returns cluster on a pedestrian or a car);
///  - memory: a map cell (the map's voxel) where something was seen moving in the last `memory_s`
///    seconds holds no map point: its points leave the map, and a scan's points that fall in it
///    are neither registered nor added (a mover's earlier returns, left in the map, would pull
///    the registration along with it).
/// "Seen moving" is stricter than the mask's outlier: the point's Doppler differs from a static
/// point's by more than min_radial_speed_mps (noise and aliasing aside: the front end decides it)
/// and at least min_cluster_points such points lie within neighbour_radius_m of each other (a
/// ghost or a noisy return is alone; a mover is not).

#include <Eigen/Core>
#include <unordered_map>
#include <vector>

#include "dorado/mapping/voxel_key.hpp"

namespace dorado::mapping {

struct MoverConfig {
    /// Points this close to a point flagged moving in the same scan are dropped too [m] (0: off).
    double neighbour_radius_m = 0.0;
    /// A cell where a moving point was seen stays out of the map this long [s] (0: off).
    double memory_s = 0.0;
    /// A mask outlier is seen moving only when its Doppler is this far from a static point's
    /// [m/s] (the front end's test, after unwrapping an aliased Doppler).
    double min_radial_speed_mps = 0.5;
    /// ...and this many such points (itself included) lie within neighbour_radius_m.
    int min_cluster_points = 2;

    /// Throws std::invalid_argument naming the first bad key.
    void Validate() const;
};

/// For each column of `points`: whether a column of `moving` lies within radius_m (brute force:
/// a radar scan has hundreds of points). All false for radius_m <= 0 or no moving points.
[[nodiscard]] std::vector<bool> NearAny(const Eigen::Matrix3Xd &points,
                                        const Eigen::Matrix3Xd &moving, double radius_m);

/// The columns of `moving` that have at least min_points columns (themselves included) within
/// radius_m: the clustered ones, evidence of a mover. With radius_m <= 0: all of them.
[[nodiscard]] Eigen::Matrix3Xd Clustered(const Eigen::Matrix3Xd &moving, double radius_m,
                                         int min_points);

/// The map cells where something was seen moving recently (the memory rule above).
class MoverMemory {
  public:
    MoverMemory(const MoverConfig &config, double cell_m);

    /// Marks the cells of moving points (world frame) seen at time_s, and forgets the cells last
    /// marked more than memory_s before it. Returns the cells marked now (for the map to drop).
    std::vector<VoxelKey> Observe(const Eigen::Matrix3Xd &moving_world, double time_s);
    /// Whether p_world's cell was marked within memory_s of the last Observe.
    [[nodiscard]] bool Moving(const Eigen::Vector3d &p_world) const;
    /// Cells remembered.
    [[nodiscard]] std::size_t size() const;

  private:
    MoverConfig config_;
    double cell_m_;
    std::unordered_map<VoxelKey, double, VoxelKeyHash> last_seen_s_;  ///< cell -> time marked
};

}  // namespace dorado::mapping
