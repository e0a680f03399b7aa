#pragma once
// Private to dorado_io: one nuScenes scene's radar sweeps as the devkit's JSON tables index them
// (nutonomy/nuscenes-devkit, v1.0-*): scene (name, token), sample (scene_token), sensor (channel,
// modality), calibrated_sensor (sensor_token, translation, rotation w x y z = T_ego_sensor),
// sample_data (sample_token, calibrated_sensor_token, ego_pose_token, timestamp [us], filename),
// ego_pose (translation, rotation w x y z = T_global_ego). The tables are streamed record by record
// (a release's sample_data.json is gigabytes): only the scene's records are kept.

#include <Eigen/Geometry>

#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "dorado/io/dataset_config.hpp"

namespace dorado::io {

/// One radar channel of the scene with the calibration its sweeps use.
struct NuScenesRadar {
    std::string channel;                                            ///< e.g. RADAR_FRONT
    std::string calibration_token;                                  ///< its first sweep's
    Eigen::Isometry3d T_ego_radar = Eigen::Isometry3d::Identity();  ///< that record's pose
    std::string second_calibration;  ///< another of its sweeps' calibrations ("" when one)

    /// T_ego_radar; throws DatasetError naming sample_data.json when the sweeps have two.
    [[nodiscard]] const Eigen::Isometry3d &Mount(const NuScenesSource &source) const;
};

/// One sweep of one of the scene's radars.
struct NuScenesSweep {
    int64_t timestamp_us = 0;
    std::string file;       ///< absolute (dataroot / sample_data.filename)
    std::size_t radar = 0;  ///< index into NuScenesScene::radars
};

struct NuScenesScene {
    std::vector<NuScenesRadar> radars;  ///< the channels asked for, or every radar's, front first
    std::vector<NuScenesSweep> sweeps;  ///< theirs, in time order (equal times: by radar index)
};

/// "DATAROOT/VERSION/TABLE.json".
[[nodiscard]] std::string NuScenesTablePath(const NuScenesSource &source, const char *table);

/// The sweeps of @p channels (empty: every radar channel with sweeps in the scene) in the scene
/// source.scene. Throws DatasetError naming the table file, the record and the key: a table missing
/// or not JSON, a scene not in scene.json (listing those that are, with the nearest name), a
/// channel not in sensor.json or without calibrated_sensor, a sweep whose calibration is in no
/// record, a channel with two calibrations in the scene, a channel without sweeps.
[[nodiscard]] NuScenesScene IndexNuScenesScene(const NuScenesSource &source,
                                               const std::vector<std::string> &channels);

/// The ego poses of every sample_data of the scene (all channels), one per time, in time order:
/// (timestamp [us], T_global_ego). Throws DatasetError as IndexNuScenesScene.
[[nodiscard]] std::vector<std::pair<int64_t, Eigen::Isometry3d>> NuScenesEgoPoses(
    const NuScenesSource &source);

}  // namespace dorado::io
