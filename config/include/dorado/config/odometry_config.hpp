#pragma once
/// @file odometry_config.hpp
/// The odometry configuration file (configs/odometry.yaml) -> dorado::odometry config structs.

#include <string>
#include <vector>

#include "dorado/config/field_yaml.hpp"

#include "dorado/odometry/odometry_fields.hpp"

namespace dorado::config {

/// Reads and validates an odometry YAML file. Unknown keys, wrong types and bad values throw
/// io::ConfigError naming the file and the key (e.g. "odometry.yaml: key
/// 'ego_velocity.gate_sigmas'").
[[nodiscard]] odometry::DopplerOdometryConfig LoadOdometryConfig(const std::string &yaml_path);

/// @p config as an odometry YAML file (what LoadOdometryConfig reads back), keys with docs.
[[nodiscard]] std::string OdometryConfigYaml(const odometry::DopplerOdometryConfig &config);
/// Every key of the odometry file with its built-in default and doc.
[[nodiscard]] std::vector<FieldRow> OdometryConfigFields();

/// odometry::ParseOdometryMethod, throwing io::ConfigError naming `what` (a key or a flag).
[[nodiscard]] odometry::OdometryMethod ParseOdometryMethodKey(const std::string &text,
                                                              const std::string &what);

}  // namespace dorado::config
