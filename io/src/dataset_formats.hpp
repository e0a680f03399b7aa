#pragma once
// Private to dorado_io: the dataset description's sections for the data sets' own formats
// (radarscenes:, nuscenes:), kept out of dataset_config.cpp's general keys.

#include <yaml-cpp/yaml.h>

#include <filesystem>

#include "dorado/io/dataset_config.hpp"
#include "dorado/io/yaml_section.hpp"

namespace dorado::io {

/// Reads `radarscenes:` and `nuscenes:` (paths relative to @p base_dir) and checks the keys the
/// configured reader needs. Throws ConfigError naming the file and the key.
void ReadFormatSections(YamlSection &top, const std::filesystem::path &base_dir,
                        DatasetConfig &config);

/// For these readers without extrinsics.T_base_radar in the YAML: the data set's published mount.
/// Throws ConfigError naming the file that lacks it.
void ApplyFormatMount(DatasetConfig &config);

/// The section of the configured format reader, as ReadFormatSections reads it back.
void EmitFormatSection(YAML::Emitter &out, const DatasetConfig &config);

}  // namespace dorado::io
