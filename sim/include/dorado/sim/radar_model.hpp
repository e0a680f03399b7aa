#pragma once
/// @file radar_model.hpp
/// A 4D imaging radar (Hugin-like): which reflectors it detects, and how it measures them.
///
/// Per scan: reflectors in range and field of view; hidden ones (behind opaque boxes or behind a
/// hill) removed; a detection when SNR = radar constant + RCS - 40 log10(range) + antenna gain,
/// with Swerling-1 fading, exceeds the threshold (so detection probability falls with range);
/// noisy range, azimuth, elevation and Doppler (Doppler noise grows for weak returns); ground
/// returns at short range, angular-ambiguity ghosts, double-bounce and ground-multipath ghosts,
/// clutter with random Doppler, optional Doppler aliasing. Points come from the noisy polar
/// measurement, in the radar frame; Doppler is positive for receding points.

#include <Eigen/Geometry>
#include <cstdint>
#include <random>
#include <vector>

#include "dorado/core/radar_scan.hpp"
#include "dorado/sim/moving_objects.hpp"
#include "dorado/sim/sequence_config.hpp"
#include "dorado/sim/terrain.hpp"
#include "dorado/sim/world.hpp"

namespace dorado::sim {

/// What produced a detection (kept beside the scan for statistics and tests).
enum class PointSource : uint8_t { kStatic, kGround, kMoving, kGhost, kClutter };

struct SimulatedScan {
    RadarScan scan;  ///< azimuth_rad holds the Hugin's azimuth (measured from the Y axis)
    std::vector<PointSource> source;  ///< one per point
};

class RadarModel {
  public:
    RadarModel(const RadarConfig &config, const Terrain &terrain, const StaticWorld &world,
               const MovingObjects &moving);

    /// One scan at t [s since start] from the radar at T_world_radar moving with v_world_radar
    /// (velocity of the radar's origin in the world frame).
    [[nodiscard]] SimulatedScan Measure(double t, const Eigen::Isometry3d &T_world_radar,
                                        const Eigen::Vector3d &v_world_radar,
                                        std::mt19937_64 &rng) const;

  private:
    const RadarConfig config_;
    const Terrain &terrain_;
    const StaticWorld &world_;
    const MovingObjects &moving_;
    std::vector<Eigen::Vector3d> cell_directions_;  ///< occlusion cells' central rays
};

/// The Hugin reports azimuth from its Y axis: 90 deg is straight ahead (+X).
[[nodiscard]] inline double HuginAzimuth(double x, double y) {
    return std::atan2(x, y);
}

}  // namespace dorado::sim
