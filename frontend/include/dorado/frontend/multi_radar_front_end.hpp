#pragma once
/// @file multi_radar_front_end.hpp
/// Several 2D radars on one vehicle, each firing at its own time, into one map (no I/O).
///
/// Per radar scan, at that scan's own stamp:
///   1. the radar's planar ego-velocity and its dynamic mask (RANSAC, eq. 2, in its own frame);
///   2. the vehicle's planar twist filter updated by it (odometry::PlanarTwistFilter): radars at
///      different places observe the yaw rate together, none paired with another's instant;
///   3. the scan kept for the sweep: its static points (and its moving ones, for the mover rules).
/// When the first radar of the list (the reference) fires, the sweep since its previous scan
/// closes: every kept scan's points are brought into the base frame at the reference stamp
/// through their radar's mount and the filter's twist over the time between the two stamps, and
/// that one cloud is registered against the map (mapping::RadarMapper, planar) with the motion
/// prior. One radar is the special case with nothing to merge.

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "dorado/core/extrinsics.hpp"
#include "dorado/core/imu.hpp"
#include "dorado/core/radar_scan.hpp"
#include "dorado/core/trajectory.hpp"
#include "dorado/frontend/radar_front_end.hpp"
#include "dorado/odometry/planar_twist_filter.hpp"

namespace dorado::frontend {

/// What one radar's scan did (every scan, whether or not it closed a sweep).
struct RadarScanStep {
    std::size_t radar = 0;
    int64_t stamp_ns = 0;
    /// False when the scan was older than the sweep already closed: not used (skip_reason).
    bool accepted = false;
    std::string skip_reason;
    odometry::EgoVelocityResult ego;  ///< this radar's own ego-velocity and mask
    odometry::TwistUpdate twist_update = odometry::TwistUpdate::kInvalid;
    /// The filter's twist after this scan: (v_x, v_y, yaw rate) of the base, and covariance.
    Eigen::Vector3d twist = Eigen::Vector3d::Zero();
    Eigen::Matrix3d twist_covariance = Eigen::Matrix3d::Zero();
    /// When this scan was the reference radar's: the sweep it closed, registered (the
    /// FrontEndResult of a one-radar front end, its static_mask over the merged cloud).
    std::optional<FrontEndResult> sweep;
    int sweep_radars = 0;  ///< radars whose scans joined the sweep
};

class MultiRadarFrontEnd {
  public:
    /// config.odometry.ego_velocity is every radar's estimator; config.prior, use_mask, mapper
    /// and prior_noise as in RadarFrontEnd (mapper on). T_base_radars[0] is the reference radar.
    /// Throws std::invalid_argument on a bad config, no radar, or a 3-D radar geometry.
    MultiRadarFrontEnd(FrontEndConfig config, std::vector<Eigen::Isometry3d> T_base_radars,
                       const Eigen::Isometry3d &T_base_imu, const VehicleGeometry &geometry,
                       odometry::PlanarTwistFilterConfig twist_filter = {});
    ~MultiRadarFrontEnd();
    MultiRadarFrontEnd(MultiRadarFrontEnd &&) noexcept;
    MultiRadarFrontEnd &operator=(MultiRadarFrontEnd &&) noexcept;

    /// Buffers one IMU sample (IMU frame) for the imu and imu+doppler priors.
    void AddImu(const ImuSample &sample);
    /// Processes radar @p radar's scan (its own frame, its own stamp). Never throws on bad data;
    /// throws std::out_of_range for a radar index beyond the list.
    RadarScanStep Process(std::size_t radar, const RadarScan &scan_radar);

    /// The end of the drive: the sweeps' poses still in the mapper's smoother, written (and
    /// appended to trajectory()). No Process after it.
    std::vector<mapping::WrittenPose> Finish();
    /// One written (smoothed) pose per closed sweep, at the reference radar's stamps, about
    /// mapper.smoother.lag_s behind the newest sweep until Finish.
    [[nodiscard]] const Trajectory &trajectory() const;
    [[nodiscard]] std::size_t radars() const;
    /// The twist filter: the twist now, and each radar's mount as calibrated so far.
    [[nodiscard]] const odometry::PlanarTwistFilter &twist_filter() const;

  private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace dorado::frontend
