#pragma once
// Private to dorado_io: the dataset description's sections for the data sets' own formats
// (radarscenes:, nuscenes:), kept out of dataset_config.cpp's general keys.

#include "dorado/io/dataset_config.hpp"
#include "dorado/io/field_yaml.hpp"

namespace dorado::io {

/// Checks the keys of `radarscenes:` and `nuscenes:` that the configured reader needs. Throws
/// ConfigError naming the file and the key.
void CheckFormatSections(FieldReader &in, const DatasetConfig &config);

/// The command line's `--scene` / `--sequence` over nuscenes.scene / radarscenes.sequence_dir.
/// Throws ConfigError for a choice the reader has no use for, and for a sequence folder that is not
/// there (listing those that are, with the nearest name).
void ApplyDatasetChoice(DatasetConfig &config, const DatasetChoice &choice);

/// For these readers, what the data set publishes: with every radar (radarscenes.sensor_id 0,
/// nuscenes.channel empty) the `radars:` list (each radar's mount), the first also the one radar;
/// the one radar's mount unless @p mount_given (extrinsics.T_base_radar in the YAML); nuScenes' CAN
/// bus IMU file when imu.path is empty. Throws ConfigError naming the description and the data
/// set's file that is missing or malformed.
void ApplyFormatLayout(DatasetConfig &config, bool mount_given);

}  // namespace dorado::io
