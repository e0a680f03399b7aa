#include "dorado/config/odometry_config.hpp"

#include <stdexcept>

#include "dorado/io/yaml_section.hpp"

namespace dorado::config {
namespace {

using odometry::CovarianceModel;
using odometry::PowerWeighting;
using odometry::RobustMethod;
using odometry::TrimMode;

void ReadEgoVelocity(io::YamlSection m, odometry::EgoVelocityConfig &c) {
    m.Read("min_range_m", c.min_range_m);
    m.Read("max_range_m", c.max_range_m);
    m.Read("min_azimuth_deg", c.min_azimuth_deg);
    m.Read("max_azimuth_deg", c.max_azimuth_deg);
    m.Read("min_elevation_deg", c.min_elevation_deg);
    m.Read("max_elevation_deg", c.max_elevation_deg);
    m.Read("min_power_db", c.min_power_db);
    m.Read("use_power", c.use_power);
    m.ReadEnum("power_weighting", c.power_weighting,
               {{"snr", PowerWeighting::kSnr},
                {"linear", PowerWeighting::kLinear},
                {"decibel", PowerWeighting::kDecibel}});
    m.Read("snr_reference_db", c.snr_reference_db);
    m.Read("decibel_floor_db", c.decibel_floor_db);
    m.ReadEnum("method", c.method,
               {{"ransac", RobustMethod::kRansac},
                {"trimmed_irls", RobustMethod::kTrimmedIrls},
                {"none", RobustMethod::kNone}});
    m.Read("doppler_sigma_mps", c.doppler_sigma_mps);
    m.Read("gate_sigmas", c.gate_sigmas);
    m.Read("max_gate_scale", c.max_gate_scale);
    m.Read("ransac_success_probability", c.ransac_success_probability);
    m.Read("ransac_min_iterations", c.ransac_min_iterations);
    m.Read("ransac_max_iterations", c.ransac_max_iterations);
    m.Read("ransac_score_points", c.ransac_score_points);
    m.Read("ransac_bailout_points", c.ransac_bailout_points);
    m.Read("ransac_bailout_fraction", c.ransac_bailout_fraction);
    m.Read("score_cells_azimuth", c.score_cells_azimuth);
    m.Read("score_cells_elevation", c.score_cells_elevation);
    m.Read("refit_iterations", c.refit_iterations);
    m.Read("seed", c.seed);
    m.ReadEnum(
        "trim_mode", c.trim_mode,
        {{"percent", TrimMode::kPercent}, {"mad", TrimMode::kMad}, {"fixed", TrimMode::kFixed}});
    m.Read("trim_value", c.trim_value);
    m.Read("irls_max_iterations", c.irls_max_iterations);
    m.ReadEnum("covariance", c.covariance,
               {{"sandwich", CovarianceModel::kSandwich},
                {"residual_scaled", CovarianceModel::kResidualScaled}});
    m.Read("min_points", c.min_points);
    m.Read("min_inliers", c.min_inliers);
    m.Read("min_inlier_ratio", c.min_inlier_ratio);
    m.Read("max_condition_number", c.max_condition_number);
    m.Read("max_speed_mps", c.max_speed_mps);
    m.Read("stationary_speed_mps", c.stationary_speed_mps);
    m.Read("compensate_direction_noise", c.compensate_direction_noise);
    m.RejectUnknownKeys();
}

void ReadGround(io::YamlSection m, odometry::GroundAttitudeConfig &c) {
    m.Read("enabled", c.enabled);
    m.Read("road_slope_sigma_deg", c.road_slope_sigma_deg);
    m.Read("road_correlation_m", c.road_correlation_m);
    m.Read("attitude_random_walk_deg_per_sqrt_s", c.attitude_random_walk_deg_per_sqrt_s);
    m.Read("initialize_from_ground", c.initialize_from_ground);
    m.Read("max_innovation_chi2", c.max_innovation_chi2);
    odometry::GroundPlaneConfig &p = c.plane;
    if (m.Has("base_height_m"))
        m.Fail("base_height_m",
               "the base's height above the road is the vehicle's: the dataset's "
               "vehicle.base_height_m");
    m.Read("height_window_m", p.height_window_m);
    m.Read("max_tilt_deg", p.max_tilt_deg);
    m.Read("min_distance_m", p.min_distance_m);
    m.Read("max_distance_m", p.max_distance_m);
    m.Read("inlier_threshold_m", p.inlier_threshold_m);
    m.Read("ransac_iterations", p.ransac_iterations);
    m.Read("min_points", p.min_points);
    m.Read("min_depth_spread_m", p.min_depth_spread_m);
    m.Read("max_residual_sigma_m", p.max_residual_sigma_m);
    m.Read("elevation_sigma_deg", p.elevation_sigma_deg);
    m.Read("seed", p.seed);
    m.RejectUnknownKeys();
}

void ReadOnlineCalibration(io::YamlSection m, odometry::YawCalibrationConfig &c) {
    m.Read("enabled", c.enabled);
    m.Read("warmup_s", c.warmup_s);
    m.Read("window_s", c.window_s);
    m.Read("max_window_s", c.max_window_s);
    m.Read("min_turn_rad", c.min_turn_rad);
    m.Read("min_speed_mps", c.min_speed_mps);
    m.Read("measurement_sigma_rad", c.measurement_sigma_rad);
    m.Read("relative_sigma", c.relative_sigma);
    m.Read("initial_relative_sigma", c.initial_relative_sigma);
    m.Read("relative_random_walk_per_sqrt_s", c.relative_random_walk_per_sqrt_s);
    m.Read("max_innovation_chi2", c.max_innovation_chi2);
    m.Read("max_ratio", c.max_ratio);
    m.RejectUnknownKeys();
}

}  // namespace

odometry::OdometryMethod ParseOdometryMethodKey(const std::string &text, const std::string &what) {
    try {
        return odometry::ParseOdometryMethod(text);
    } catch (const std::invalid_argument &e) {
        throw io::ConfigError(what + ": " + e.what());
    }
}

odometry::DopplerOdometryConfig LoadOdometryConfig(const std::string &yaml_path) {
    odometry::DopplerOdometryConfig config;
    io::YamlSection top(io::LoadYamlFile(yaml_path), yaml_path);
    ReadEgoVelocity(top.Child("ego_velocity"), config.ego_velocity);
    io::YamlSection odo = top.Child("odometry");
    if (odo.Has("rotation")) {
        throw io::ConfigError(
            yaml_path +
            ": key 'odometry.rotation' is now 'odometry.method' (doppler | imu "
            "| imu+doppler; the old 'imu' is 'imu+doppler', 'imu-only' is 'imu')");
    }
    if (odo.Has("method")) {
        config.method = ParseOdometryMethodKey(odo.Get<std::string>("method", ""),
                                               yaml_path + ": key 'odometry.method'");
    }
    odo.Read("zero_velocity_update", config.zero_velocity_update);
    odo.Read("max_angular_rate_radps", config.max_angular_rate_radps);
    odo.Read("angular_rate_prior", config.angular_rate_prior);
    odo.RejectUnknownKeys();
    ReadGround(top.Child("ground"), config.ground);
    ReadOnlineCalibration(top.Child("online_calibration"), config.online_calibration);
    top.RejectUnknownKeys();
    try {
        config.Validate();  // messages name the field as "section.key: ..."
    } catch (const std::invalid_argument &e) {
        const std::string what = e.what();
        const auto colon = what.find(':');
        throw io::ConfigError(yaml_path + ": key '" + what.substr(0, colon) + "'" +
                              what.substr(colon));
    }
    return config;
}

}  // namespace dorado::config
