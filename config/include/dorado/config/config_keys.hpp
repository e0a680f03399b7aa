#pragma once
/// @file config_keys.hpp
/// docs/config_keys.md: every key of configs/odometry.yaml, configs/mapper.yaml, the dataset
/// descriptions, the simulated sequences and the bench files with its
/// built-in default and meaning, generated from the field lists (`dorado config keys`).

#include <string>

namespace dorado::config {

/// The whole page, as `dorado config keys` prints it and docs/config_keys.md holds it.
[[nodiscard]] std::string ConfigKeysMarkdown();

}  // namespace dorado::config
