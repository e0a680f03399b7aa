#pragma once
// Private to dorado_io: the dataset description's sections for the data sets' own formats
// (radarscenes:, nuscenes:), kept out of dataset_config.cpp's general keys.

#include "dorado/io/dataset_config.hpp"
#include "dorado/io/field_yaml.hpp"

namespace dorado::io {

/// Checks the keys of `radarscenes:` and `nuscenes:` that the configured reader needs. Throws
/// ConfigError naming the file and the key.
void CheckFormatSections(FieldReader &in, const DatasetConfig &config);

/// For these readers without extrinsics.T_base_radar in the YAML: the data set's published mount.
/// Throws ConfigError naming the file that lacks it.
void ApplyFormatMount(DatasetConfig &config);

}  // namespace dorado::io
