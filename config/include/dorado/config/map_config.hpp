#pragma once
/// @file map_config.hpp
/// The mapper configuration file (configs/mapper.yaml) -> dorado::mapping config structs, and
/// the mapper's enum keys.

#include <string>
#include <vector>

#include "dorado/config/field_yaml.hpp"
#include "dorado/loops/loop_fields.hpp"
#include "dorado/mapping/mapper_fields.hpp"

#include "dorado/mapping/motion_prior.hpp"
#include "dorado/mapping/radar_mapper.hpp"

namespace dorado::config {

struct MapCommandConfig {
    mapping::MapperConfig mapper;
    mapping::PriorNoiseConfig prior;
    loops::LoopClosureConfig loop_closure;
};

/// The whole file's fields: mapper.*, prior.*, loop_closure.* (map.pcd / map.ply / map.png are the
/// mapper's own map: its points as added, no output setting).
template <typename Visitor>
void VisitFields(MapCommandConfig &c, Visitor &&v) {
    VisitFields(c.mapper, Prefixed{"mapper.", v});
    VisitFields(c.prior, Prefixed{"prior.", v});
    VisitFields(c.loop_closure, Prefixed{"loop_closure.", v});
}

/// Reads and validates a mapper YAML file. Unknown keys, wrong types and bad values throw
/// io::ConfigError naming the file and the key (e.g. "mapper.yaml: key 'mapper.scan_voxel_m'").
[[nodiscard]] MapCommandConfig LoadMapConfig(const std::string &yaml_path);

/// @p config as a mapper YAML file (what LoadMapConfig reads back), each key with its doc.
[[nodiscard]] std::string MapConfigYaml(const MapCommandConfig &config);
/// Every key of the mapper file with its built-in default and doc.
[[nodiscard]] std::vector<FieldRow> MapConfigFields();

/// mapping::ParsePriorKind, throwing io::ConfigError naming `what` (a key or a flag).
[[nodiscard]] mapping::PriorKind ParsePriorKindKey(const std::string &text,
                                                   const std::string &what);

}  // namespace dorado::config
