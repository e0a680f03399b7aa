#pragma once
/// @file paper_estimator.hpp
/// The paper node's estimator parameters (threshold_mode, threshold_value) on dorado's ego-velocity
/// settings, without ROS: node_settings.cpp reads the parameters, this maps them.

#include <optional>
#include <string>

#include "dorado/odometry/ego_velocity.hpp"

namespace dorado::ros_node {

/// Applies threshold_mode / threshold_value (nullopt = not given) to @p ego. "ransac": RANSAC with
/// the inlier gate of strong returns = value [m/s] (doppler_sigma_mps = value / gate_sigmas);
/// "percent", "mad", "fixed": trimmed_irls with that trim_mode and trim_value = value. Without a
/// mode, a RANSAC @p ego takes the value as its gate and any other keeps its method. Throws
/// io::ConfigError "parameter 'threshold_mode': unknown threshold_mode 'x' (ransac, percent, mad,
/// fixed)" for any other mode.
void ApplyPaperThreshold(const std::optional<std::string> &mode, const std::optional<double> &value,
                         odometry::EgoVelocityConfig &ego);

}  // namespace dorado::ros_node
