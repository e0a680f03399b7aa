#pragma once
/// @file inertial_check.hpp
/// The Doppler ego-velocity against an IMU, for recordings without ground truth: over short
/// windows, the change of the Doppler velocity (rotated into a world frame by the integrated gyro)
/// must equal the accelerometer's integral (gravity removed). It says which Doppler sign is right
/// (the ego-velocity fit itself cannot: flipping every Doppler flips v, with the same residuals),
/// how well the extrinsic rotation fits, and at which time offset the scans agree best.

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <vector>

#include "dorado/core/extrinsics.hpp"
#include "dorado/core/imu.hpp"

namespace dorado::odometry {

/// One scan's valid ego-velocity (radar frame) at its stamp.
struct StampedRadarVelocity {
    int64_t stamp_ns = 0;
    Eigen::Vector3d v_radar_mps = Eigen::Vector3d::Zero();
};

struct InertialCheckConfig {
    double window_s = 0.5;  ///< time between the two scans of a comparison window
    /// The first rest_s of IMU data must be at rest: the gyro bias and gravity come from it.
    double rest_s = 1.0;
    /// Windows whose Doppler speed is below this at both ends are left out (a rig at rest agrees
    /// trivially and would dilute the residual).
    double min_speed_mps = 0.1;
    /// > 0: also search the scan time offset in [-max, max] (step time_offset_step_s).
    double max_time_offset_s = 0.0;
    double time_offset_step_s = 0.005;
};

/// The comparison at one time offset and one Doppler sign.
struct InertialFit {
    int windows = 0;
    /// Least-squares k in dv_imu = k dv_doppler: 1 when sign, rotation and scale are right, about
    /// -1 for a flipped Doppler sign, near 0 for a wrong extrinsic rotation.
    double slope = std::numeric_limits<double>::quiet_NaN();
    double rms_residual_mps = std::numeric_limits<double>::quiet_NaN();  ///< RMS |dv_imu - dv_dop|
    double rms_delta_v_mps = std::numeric_limits<double>::quiet_NaN();   ///< RMS |dv_doppler|
};

struct InertialCheck {
    InertialFit as_given;  ///< the Doppler sign and stamps as given
    InertialFit flipped;   ///< every Doppler negated (v_radar -> -v_radar)
    /// +1 when the sign as given fits better, -1 when the flipped one does, 0 without windows.
    int doppler_sign = 0;
    /// The scan time offset (added to the stamps) with the smallest residual, and that fit (with
    /// the better sign); 0 and as_given without a search.
    double best_time_offset_s = 0.0;
    InertialFit at_best_offset;
    /// The small rotation C (rotation vector, base frame) that best aligns the Doppler velocity
    /// changes with the accelerometer's when T_base_radar's rotation becomes C R_base_radar
    /// (linearised least squares at the given stamps and the better sign), and the residual then.
    /// A few degrees here tilt the Doppler velocity and make the height drift.
    Eigen::Vector3d rotation_correction_base_rad = Eigen::Vector3d::Zero();
    double rms_residual_corrected_mps = std::numeric_limits<double>::quiet_NaN();
    Eigen::Vector3d gyro_bias_imu_radps = Eigen::Vector3d::Zero();  ///< from the rest window
    Eigen::Vector3d specific_force_at_rest_imu_mps2 = Eigen::Vector3d::Zero();
    double rest_gyro_rms_radps = 0.0;  ///< RMS gyro deviation in the rest window (at rest: noise)
};

/// Compares the velocities with the IMU. `imu` in time order (the IMU frame); the base frame is
/// Extrinsics' (T_base_radar, T_base_imu). The velocity is compared at the IMU: the radar's
/// velocity plus the lever-arm term omega x (p_imu - p_radar) from the gyro. Throws
/// std::invalid_argument when the IMU data do not cover a rest window and the scans.
[[nodiscard]] InertialCheck CompareWithImu(const std::vector<StampedRadarVelocity> &velocities,
                                           const std::vector<ImuSample> &imu,
                                           const Extrinsics &extrinsics,
                                           const InertialCheckConfig &config = {});

}  // namespace dorado::odometry
