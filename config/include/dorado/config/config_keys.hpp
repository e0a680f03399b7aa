#pragma once
/// @file config_keys.hpp
/// docs/config_keys.md: every key of configs/odometry.yaml and configs/mapper.yaml with its
/// built-in default and meaning, generated from the field lists (`dorado config keys`).

#include <string>

namespace dorado::config {

/// The whole page, as `dorado config keys` prints it and docs/config_keys.md holds it.
[[nodiscard]] std::string ConfigKeysMarkdown();

}  // namespace dorado::config
