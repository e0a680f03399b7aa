#pragma once
/// @file map_config.hpp
/// The mapper configuration file (configs/mapper.yaml) -> dorado::mapping config structs.

#include <string>

#include "dorado/mapping/motion_prior.hpp"
#include "dorado/mapping/radar_mapper.hpp"

namespace dorado::apps {

struct MapCommandConfig {
    mapping::MapperConfig mapper;
    mapping::PriorNoiseConfig prior;
    double output_voxel_m = 0.3;  ///< density of map.pcd / map.ply / map.png
};

/// Reads and validates a mapper YAML file. Unknown keys, wrong types and bad values throw
/// io::ConfigError naming the file and the key (e.g. "mapper.yaml: key 'mapper.scan_voxel_m'").
[[nodiscard]] MapCommandConfig LoadMapConfig(const std::string &yaml_path);

}  // namespace dorado::apps
