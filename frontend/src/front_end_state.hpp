#pragma once
// Internal: RadarFrontEnd's state between scans and the steps of its per-scan loop
// (radar_front_end.cpp): the motion prior and the twist's continuity in motion_prior_step.cpp,
// the configs each part runs with in front_end_config.cpp.

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>

#include "built_prior.hpp"
#include "dorado/core/gyro_bias.hpp"
#include "dorado/frontend/radar_front_end.hpp"

namespace dorado::frontend {

/// With the mapper on, the odometry's method follows the prior (front_end_config.cpp). Throws
/// std::invalid_argument for the doppler prior on an unconstrained platform.
[[nodiscard]] odometry::DopplerOdometryConfig OdometryConfigFor(const FrontEndConfig &config,
                                                                const VehicleGeometry &geometry);

/// The prior's twist: the odometry's, as integrated (motion_prior_step.cpp).
[[nodiscard]] Twist PriorTwist(const odometry::OdometryStep &step);

/// What the mapper made of one scan (steps 2-3 of Process).
struct MappedScan {
    BuiltPrior prior;
    double prior_ms = 0.0;
    mapping::RegistrationResult registration;
    odometry::YawCalibrationStep yaw_calibration;
};

struct RadarFrontEnd::State {
    State(FrontEndConfig c, const Extrinsics &e, const VehicleGeometry &g);

    FrontEndConfig config;
    Extrinsics extrinsics;
    VehicleGeometry geometry;
    odometry::DopplerOdometry odometry;
    std::optional<mapping::RadarMapper> mapper;
    ImuWindow imu;
    GyroBiasEstimator gyro_bias;  // from the stationary scans, subtracted from every gyro rate
    // eq. (5)'s yaw lever from the map's registered yaw (odometry.online_calibration).
    std::optional<odometry::YawRateCalibrator> yaw_calibrator;
    Trajectory trajectory;
    Eigen::Isometry3d T_world_base_initial = Eigen::Isometry3d::Identity();
    // The last two accepted poses since the last reset (constvel, imu priors).
    int scans_since_reset = 0;
    Eigen::Isometry3d T_world_base_prev = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_world_base_prev2 = Eigen::Isometry3d::Identity();
    double last_dt_s = 0.0;
    bool has_last = false;
    int64_t last_stamp_ns = 0;
    // The previous scan's Doppler twist, when it was a measurement (the trapezoid prior).
    std::optional<Twist> last_twist;
    // The last twist that passed the continuity test, and the time since it [s].
    std::optional<Twist> last_plausible_twist;
    double since_plausible_s = 0.0;

    // motion_prior_step.cpp
    /// Whether this scan's Doppler twist is continuous with the last plausible one (and, when it
    /// is, the new last plausible one).
    bool TwistIsContinuous(const odometry::OdometryStep &step);
    /// The prior (config.prior) for the scan at stamp_ns, dt_s after the previous one, or
    /// constvel in its stead when its inputs are missing (twist_discontinuous: the Doppler
    /// twist jumped).
    [[nodiscard]] BuiltPrior BuildPrior(const odometry::OdometryStep &step, int64_t stamp_ns,
                                        double dt_s, bool twist_discontinuous) const;

    // radar_front_end.cpp
    /// The interval's mean gyro rate in the base frame, bias removed (NaN before a first scan).
    [[nodiscard]] Eigen::Vector3d MeanGyroBase(int64_t stamp_ns) const;
    /// Steps 2-3: the prior, then the mapper's registration, smoothing and map update (with the
    /// static mask when use_mask, the ground when the prior does not hold the attitude itself),
    /// then the yaw lever's calibration.
    [[nodiscard]] MappedScan MapScan(const RadarScan &scan_radar,
                                     const odometry::OdometryStep &step,
                                     const mapping::PointMask &static_mask, bool use_mask,
                                     bool twist_discontinuous);
    /// The registered pose's yaw handed to the calibrator; its new estimate drives the next
    /// scans (odometry.SetYawLever).
    [[nodiscard]] odometry::YawCalibrationStep CalibrateYawLever(
        const odometry::OdometryStep &step, const mapping::RegistrationResult &registration);
    /// The scan's pose becomes the previous one (the next prior's start); the written poses
    /// join the trajectory.
    void Advance(int64_t stamp_ns, const odometry::OdometryStep &step,
                 const Eigen::Isometry3d &T_world_base, bool twist_discontinuous,
                 const std::vector<mapping::WrittenPose> *written);
};

}  // namespace dorado::frontend
