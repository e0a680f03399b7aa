#pragma once
/// @file config_keys.hpp
/// docs/config_keys.md: every key of configs/odometry.yaml, configs/mapper.yaml, the dataset
/// descriptions, the simulated sequences and the bench files with its
/// built-in default and meaning, generated from the field lists (`dorado config keys`).
/// It lives in apps/ because it gathers the field lists of every layer (config, io, sim, bench);
/// config/ itself knows only the odometry and mapper files.

#include <string>

namespace dorado::apps {

/// The whole page, as `dorado config keys` prints it and docs/config_keys.md holds it.
[[nodiscard]] std::string ConfigKeysMarkdown();

}  // namespace dorado::apps
