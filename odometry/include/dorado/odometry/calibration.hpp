#pragma once
/// @file calibration.hpp
/// The paper's sensor calibration (section IV-A) on plain per-scan data: the radar's rotation in
/// two steps (straight driving, then free driving on flat ground) and its position s_x from a gyro.

#include <Eigen/Core>
#include <vector>

namespace dorado::odometry {

struct RotationCalibration {
    Eigen::Matrix3d R_base_radar = Eigen::Matrix3d::Identity();
    double rms_residual_mps = 0.0;  ///< RMS of the velocity components the step drives to zero
    double sigma_rad = 0.0;         ///< 1-sigma uncertainty of the angle(s) this step estimates
    int samples = 0;
};

/// Step 1: from radar velocities recorded while driving straight forward and backward, the
/// rotation that maps every velocity onto the base X axis (zero Y and Z). The forward direction is
/// the principal axis of the velocities, signed to agree with `R_base_radar_guess`; the roll about
/// X is left as in the guess (step 2 determines it). Throws std::invalid_argument with fewer than
/// 3 samples or no motion.
/// @p correlation_lag > 0: the samples' errors are taken as correlated over that many neighbours
/// (slip, vibration, a slowly wandering ground truth): sigma_rad is then the Newey-West estimate,
/// never below the independent-noise one.
[[nodiscard]] RotationCalibration CalibrateRotation(
    const std::vector<Eigen::Vector3d> &v_radar,
    const Eigen::Matrix3d &R_base_radar_guess = Eigen::Matrix3d::Identity(),
    int correlation_lag = 0);

/// Step 2: from radar velocities recorded while driving freely (with turns) on flat ground, the
/// roll about the base X axis that zeroes the base Z velocity, applied on top of `R_base_radar`
/// (the result of step 1). Of the two solutions (alpha, alpha + pi) the one closer to no change is
/// returned. Throws std::invalid_argument with fewer than 3 samples or when the Y-Z velocities
/// have no dominant direction (no turns: the roll is unobservable).
[[nodiscard]] RotationCalibration CalibrateRoll(const std::vector<Eigen::Vector3d> &v_radar,
                                                const Eigen::Matrix3d &R_base_radar);

struct SxCalibration {
    double s_x_m = 0.0;  ///< radar X position relative to the rear axle (Z-ICR)
    double sigma_m = 0.0;
    double rms_residual_mps = 0.0;
    int samples = 0;
    int inliers = 0;
};

/// s_x from driving in a flat circle: per sample the radar velocity in the base frame and the gyro
/// yaw rate in the base frame; the kinematic model says v_sy = omega_z s_x (eq. 3 with
/// omega_x = 0). Least squares through the origin with iterative 3-sigma (MAD) rejection.
/// Throws std::invalid_argument on mismatched sizes, fewer than 3 samples or no yaw motion.
/// @p correlation_lag as for CalibrateRotation (sigma_m from the inliers' correlated residuals).
[[nodiscard]] SxCalibration CalibrateSx(const std::vector<Eigen::Vector3d> &v_sensor_base,
                                        const std::vector<double> &yaw_rate_base_radps,
                                        int correlation_lag = 0);

/// The Newey-West (Bartlett) long-run variance of a sum of scores: sum_i s_i^2 + 2 sum over lags
/// l = 1..lag of (1 - l / (lag + 1)) sum_i s_i s_{i-l}; the plain sum of squares for lag 0.
[[nodiscard]] double LongRunVariance(const std::vector<double> &scores, int lag);

}  // namespace dorado::odometry
