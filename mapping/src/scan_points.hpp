#pragma once
// Internal: step 1 of RadarMapper::Register, the points of a scan the mapper uses (range gate,
// static mask, movers), and the even thinning of the registration's inputs.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "dorado/core/radar_scan.hpp"
#include "dorado/mapping/measurements.hpp"
#include "dorado/mapping/movers.hpp"
#include "dorado/mapping/radar_mapper.hpp"

namespace dorado::mapping {

/// The points of a scan the mapper uses: in the range gate, finite, static by the mask, and not
/// near anything seen moving (movers.hpp).
struct ScanPoints {
    Eigen::Matrix3Xd p_base;  ///< all used points, base frame (for the map)
    std::vector<DopplerObservation> doppler;
    Eigen::Matrix3Xd moving_base;  ///< the points seen moving (clustered), base frame
    PointMask mover_dropped;       ///< per scan point: kept out by the mover rules
    /// The mover memory's cells where something moves now: the map drops what it held there.
    std::vector<VoxelKey> moving_cells;
};

/// T_world_base (the prior on the map's chain) places the points in the mover memory's cells;
/// this scan's moving points are marked in `movers` (at time_s) before the others are looked up.
[[nodiscard]] ScanPoints SelectScanPoints(const RadarScan &scan, const MapperInput &input,
                                          const Eigen::Isometry3d &T_world_base,
                                          const Eigen::Isometry3d &T_base_radar,
                                          const MapperConfig &config, MoverMemory &movers,
                                          double time_s);

/// Evenly thinned copy (the Doppler residuals: a few hundred constrain 3 velocity components
/// well).
[[nodiscard]] std::vector<DopplerObservation> Thin(const std::vector<DopplerObservation> &all,
                                                   int max_count);

/// Evenly spaced columns, at most max_count: radar scans are too sparse for a voxel grid alone to
/// bound the registration cost.
[[nodiscard]] Eigen::Matrix3Xd ThinColumns(const Eigen::Matrix3Xd &points, int max_count);

}  // namespace dorado::mapping
