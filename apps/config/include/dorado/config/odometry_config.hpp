#pragma once
/// @file odometry_config.hpp
/// The odometry configuration file (configs/odometry.yaml) -> dorado::odometry config structs.

#include <string>

#include "dorado/odometry/doppler_odometry.hpp"

namespace dorado::config {

/// Reads and validates an odometry YAML file. Unknown keys, wrong types and bad values throw
/// io::ConfigError naming the file and the key (e.g. "odometry.yaml: key
/// 'ego_velocity.gate_sigmas'").
[[nodiscard]] odometry::DopplerOdometryConfig LoadOdometryConfig(const std::string &yaml_path);

/// odometry::ParseOdometryMethod, throwing io::ConfigError naming `what` (a key or a flag).
[[nodiscard]] odometry::OdometryMethod ParseOdometryMethodKey(const std::string &text,
                                                              const std::string &what);

}  // namespace dorado::config
