#pragma once
/// @file odometry_fields.hpp
/// The odometry's configurable fields, listed once (core/config_fields.hpp): keys as in
/// configs/odometry.yaml (sections ego_velocity, odometry, ground,
/// online_calibration). The defaults are the structs'.

#include "dorado/core/config_fields.hpp"
#include "dorado/odometry/doppler_odometry.hpp"

namespace dorado::odometry {

inline Choices<PowerWeighting> PowerWeightingChoices() {
    return {{"snr", PowerWeighting::kSnr},
            {"linear", PowerWeighting::kLinear},
            {"decibel", PowerWeighting::kDecibel}};
}
inline Choices<RobustMethod> RobustMethodChoices() {
    return {{"ransac", RobustMethod::kRansac},
            {"trimmed_irls", RobustMethod::kTrimmedIrls},
            {"none", RobustMethod::kNone}};
}
inline Choices<TrimMode> TrimModeChoices() {
    return {{"percent", TrimMode::kPercent}, {"mad", TrimMode::kMad}, {"fixed", TrimMode::kFixed}};
}
inline Choices<CovarianceModel> CovarianceModelChoices() {
    return {{"sandwich", CovarianceModel::kSandwich},
            {"residual_scaled", CovarianceModel::kResidualScaled}};
}
inline Choices<OdometryMethod> OdometryMethodChoices() {
    return {{ToString(OdometryMethod::kDoppler), OdometryMethod::kDoppler},
            {ToString(OdometryMethod::kImu), OdometryMethod::kImu},
            {ToString(OdometryMethod::kImuDoppler), OdometryMethod::kImuDoppler}};
}

/// The ego-velocity estimator's fields (the sensor model is the dataset's, not listed).
template <typename Visitor>
void VisitFields(EgoVelocityConfig &c, Visitor &&v) {
    v("min_range_m", c.min_range_m, "pre-filter: closer points are dropped [m]");
    v("max_range_m", c.max_range_m, "pre-filter: farther points are dropped [m]");
    v("min_azimuth_deg", c.min_azimuth_deg, "pre-filter: azimuth from +X towards +Y [deg]");
    v("max_azimuth_deg", c.max_azimuth_deg, "pre-filter [deg]");
    v("min_elevation_deg", c.min_elevation_deg, "pre-filter: elevation from the XY plane [deg]");
    v("max_elevation_deg", c.max_elevation_deg, "pre-filter [deg]");
    v("min_power_db", c.min_power_db,
      "pre-filter: weaker points are dropped; -.inf keeps all [dB]");
    v("use_power", c.use_power, "false: unit weights in eq. (2)");
    v("power_weighting", c.power_weighting, PowerWeightingChoices(),
      "weights of eq. (2) from the power");
    v("snr_reference_db", c.snr_reference_db,
      "snr: power at which the Doppler variance doubles [dB]");
    v("decibel_floor_db", c.decibel_floor_db, "decibel: weight = max(power - floor, 0) [dB]");
    v("method", c.method, RobustMethodChoices(), "robust fit");
    v("doppler_sigma_mps", c.doppler_sigma_mps, "Doppler noise of strong returns [m/s]");
    v("gate_sigmas", c.gate_sigmas, "inlier gate = gate_sigmas * sigma_i");
    v("max_gate_scale", c.max_gate_scale, "cap on sigma_i / doppler_sigma_mps for weak returns");
    v("ransac_success_probability", c.ransac_success_probability, "RANSAC's stopping probability");
    v("ransac_min_iterations", c.ransac_min_iterations, "RANSAC hypotheses at least");
    v("ransac_max_iterations", c.ransac_max_iterations, "RANSAC hypotheses at most");
    v("ransac_score_points", c.ransac_score_points,
      "hypotheses scored on this many points (0: all)");
    v("ransac_bailout_points", c.ransac_bailout_points,
      "bail-out after this many scored points (0: off)");
    v("ransac_bailout_fraction", c.ransac_bailout_fraction,
      "bail-out below this fraction of the best");
    v("score_cells_azimuth", c.score_cells_azimuth,
      "spread-aware scoring grid (1 x 1: plain MSAC)");
    v("score_cells_elevation", c.score_cells_elevation, "spread-aware scoring grid");
    v("refit_iterations", c.refit_iterations,
      "refit-and-regate rounds (IRLS rounds for trimmed_irls)");
    v("seed", c.seed, "RANSAC's seed, reset at every scan");
    v("trim_mode", c.trim_mode, TrimModeChoices(), "trimmed_irls only");
    v("trim_value", c.trim_value, "trimmed_irls: fraction, MAD multiple or m/s");
    v("irls_max_iterations", c.irls_max_iterations, "trimmed_irls iterations");
    v("covariance", c.covariance, CovarianceModelChoices(), "covariance of the velocity");
    v("min_points", c.min_points, "validity: points left after the pre-filters");
    v("min_inliers", c.min_inliers, "validity: static inliers");
    v("min_inlier_ratio", c.min_inlier_ratio, "validity: inlier fraction");
    v("max_condition_number", c.max_condition_number, "validity: sqrt(lambda_max / lambda_min)");
    v("max_speed_mps", c.max_speed_mps, "validity: faster is invalid [m/s]");
    v("stationary_speed_mps", c.stationary_speed_mps, "slower is flagged stationary [m/s]");
    v("compensate_direction_noise", c.compensate_direction_noise,
      "gate by direction noise and remove its bias (radar.*_sigma_deg > 0)");
}

/// The ground-plane attitude correction's fields (the filter's and the plane fit's, one section).
template <typename Visitor>
void VisitFields(GroundAttitudeConfig &c, Visitor &&v) {
    v("enabled", c.enabled, "correct roll and pitch with the ground");
    v("road_slope_sigma_deg", c.road_slope_sigma_deg,
      "the road's slope about level, 1 sigma [deg]");
    v("road_correlation_m", c.road_correlation_m,
      "distance over which the slope is correlated [m]");
    v("attitude_random_walk_deg_per_sqrt_s", c.attitude_random_walk_deg_per_sqrt_s,
      "rate errors the twist covariance misses [deg/sqrt(s)]");
    v("initialize_from_ground", c.initialize_from_ground,
      "the first observation sets roll and pitch");
    v("max_innovation_chi2", c.max_innovation_chi2,
      "refuse planes beyond this chi^2 (2 dof); 0: no gate");
    GroundPlaneConfig &p = c.plane;  // base_height_m is the vehicle's, not a setting
    v("height_window_m", p.height_window_m, "candidates within this of the expected plane [m]");
    v("max_tilt_deg", p.max_tilt_deg, "largest angle of the plane from the base's XY plane [deg]");
    v("min_distance_m", p.min_distance_m, "horizontal distance of the points used [m]");
    v("max_distance_m", p.max_distance_m, "horizontal distance of the points used [m]");
    v("inlier_threshold_m", p.inlier_threshold_m, "RANSAC distance to the plane [m]");
    v("ransac_iterations", p.ransac_iterations, "RANSAC hypotheses");
    v("min_points", p.min_points, "plane inliers needed");
    v("min_depth_spread_m", p.min_depth_spread_m, "5-95 % spread of the inliers' distances [m]");
    v("max_residual_sigma_m", p.max_residual_sigma_m, "uneven ground above this residual RMS [m]");
    v("elevation_sigma_deg", p.elevation_sigma_deg,
      "radar elevation noise (the dataset's when > 0) [deg]");
    v("seed", p.seed, "RANSAC's seed, reset at every fit");
}

/// The online calibration of eq. 5's yaw lever s_x from the map (yaw_calibration.hpp).
template <typename Visitor>
void VisitFields(YawCalibrationConfig &c, Visitor &&v) {
    v("enabled", c.enabled, "estimate s_x online from the map; false: the configured s_x");
    v("warmup_s", c.warmup_s, "no measurement in the map's first seconds [s]");
    v("window_s", c.window_s, "shortest window between a measurement's two registered poses [s]");
    v("max_window_s", c.max_window_s, "a window not turning min_turn_rad by then restarts [s]");
    v("min_turn_rad", c.min_turn_rad, "smaller yaw changes are straight driving: no update [rad]");
    v("min_speed_mps", c.min_speed_mps, "mean speed of a window below this: no update [m/s]");
    v("measurement_sigma_rad", c.measurement_sigma_rad,
      "yaw error of one window's two registered poses together [rad]");
    v("relative_sigma", c.relative_sigma, "model noise relative to the yaw change");
    v("initial_relative_sigma", c.initial_relative_sigma,
      "1-sigma of the start, relative to the configured 1/s_x");
    v("relative_random_walk_per_sqrt_s", c.relative_random_walk_per_sqrt_s,
      "drift of 1/s_x, relative, per sqrt(s)");
    v("max_innovation_chi2", c.max_innovation_chi2,
      "refuse a window farther than this (chi^2, 1 dof); 0: no gate");
    v("max_ratio", c.max_ratio, "the estimate stays within [1/r, r] x the configured s_x");
}

/// configs/odometry.yaml: ego_velocity.*, odometry.*, ground.*, online_calibration.*.
template <typename Visitor>
void VisitFields(DopplerOdometryConfig &c, Visitor &&v) {
    VisitFields(c.ego_velocity, Prefixed{"ego_velocity.", v});
    v("odometry.method", c.method, OdometryMethodChoices(),
      "the rotation source (the command line's --method overrides)");
    v("odometry.zero_velocity_update", c.zero_velocity_update,
      "stationary scans integrate a zero twist");
    v("odometry.max_angular_rate_radps", c.max_angular_rate_radps,
      "a faster Doppler twist is a fallback [rad/s]");
    v("odometry.max_acceleration_mps2", c.max_acceleration_mps2,
      "RANSAC holds the radar velocity within this * dt (+ 3 sigma) of the previous scan's "
      "[m/s^2]; 0 = off");
    v("odometry.angular_rate_prior", c.angular_rate_prior,
      "integrate eq. 5's twist combined with the vehicle's angular-rate prior");
    VisitFields(c.ground, Prefixed{"ground.", v});
    VisitFields(c.online_calibration, Prefixed{"online_calibration.", v});
}

}  // namespace dorado::odometry
