#include "dataset_formats.hpp"

#include "readers.hpp"

namespace dorado::io {

void CheckFormatSections(FieldReader &in, const DatasetConfig &config) {
    if (config.reader == ReaderKind::kRadarScenes) {
        if (config.radarscenes.sequence_dir.empty())
            in.Fail("radarscenes.sequence_dir", "is required for reader: radarscenes");
        if (config.radarscenes.sensor_id < 1 || config.radarscenes.sensor_id > 4)
            in.Fail("radarscenes.sensor_id", "must be 1, 2, 3 or 4 (RadarScenes' radars)");
    }
    if (config.reader == ReaderKind::kNuScenes) {
        for (const auto &[key, value] :
             {std::pair<const char *, const std::string &>{"dataroot", config.nuscenes.dataroot},
              {"version", config.nuscenes.version},
              {"scene", config.nuscenes.scene},
              {"channel", config.nuscenes.channel}}) {
            if (value.empty())
                in.Fail(std::string("nuscenes.") + key, "is required for reader: nuscenes");
        }
    }
}

void ApplyFormatMount(DatasetConfig &config) {
    try {
        if (config.reader == ReaderKind::kRadarScenes)
            config.extrinsics.T_base_radar = RadarScenesMount(config);
        if (config.reader == ReaderKind::kNuScenes)
            config.extrinsics.T_base_radar = NuScenesMount(config);
    } catch (const DatasetError &e) {
        throw ConfigError(config.config_path + ": the radar's mount: " + e.what());
    }
}

}  // namespace dorado::io
