#include "dataset_formats.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "dorado/io/closest_name.hpp"
#include "dorado/io/dataset_fields.hpp"
#include "readers.hpp"

namespace dorado::io {

namespace fs = std::filesystem;

namespace {

std::string DescriptionName(const DatasetConfig &config) {
    return config.config_path.empty() ? config.rosbag.path : config.config_path;
}

// The folders named sequence_* beside @p dir, sorted.
std::vector<std::string> SequenceFolders(const fs::path &parent) {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto &entry : fs::directory_iterator(parent, ec)) {
        const std::string name = entry.path().filename().string();
        if (entry.is_directory() && name.rfind("sequence_", 0) == 0) names.push_back(name);
    }
    std::sort(names.begin(), names.end());
    return names;
}

}  // namespace

fs::path RadarScenesSequenceDir(const DatasetConfig &config) {
    fs::path dir = fs::path(config.radarscenes.sequence_dir).lexically_normal();
    while (!dir.has_filename() && dir.has_relative_path()) dir = dir.parent_path();
    return dir;
}

int OneRadarScenesSensor(const DatasetConfig &config) {
    if (config.radarscenes.sensor_id != 0 || config.radars.empty())
        return config.radarscenes.sensor_id;
    return config.radars.front().radarscenes_sensor_id;
}

std::string OneNuScenesChannel(const DatasetConfig &config) {
    if (!config.nuscenes.channel.empty() || config.radars.empty()) return config.nuscenes.channel;
    return config.radars.front().nuscenes_channel;
}

void CheckFormatSections(FieldReader &in, const DatasetConfig &config) {
    if (config.reader == ReaderKind::kRadarScenes) {
        if (config.radarscenes.sequence_dir.empty())
            in.Fail("radarscenes.sequence_dir", "is required for reader: radarscenes");
        if (config.radarscenes.sensor_id < 0 || config.radarscenes.sensor_id > 4)
            in.Fail("radarscenes.sensor_id",
                    "must be 1, 2, 3 or 4 (one of RadarScenes' radars), or 0 (every radar)");
    }
    if (config.reader == ReaderKind::kNuScenes) {
        for (const auto &[key, value] :
             {std::pair<const char *, const std::string &>{"dataroot", config.nuscenes.dataroot},
              {"version", config.nuscenes.version},
              {"scene", config.nuscenes.scene}}) {
            if (value.empty())
                in.Fail(std::string("nuscenes.") + key, "is required for reader: nuscenes");
        }
    }
}

void ApplyDatasetChoice(DatasetConfig &config, const DatasetChoice &choice) {
    const std::string reader = FormatValue(config.reader, ReaderKindChoices());
    if (!choice.scene.empty()) {
        if (config.reader != ReaderKind::kNuScenes)
            throw ConfigError(DescriptionName(config) + ": --scene " + choice.scene +
                              ": chooses a nuScenes scene (reader nuscenes); this description's "
                              "reader is " +
                              reader);
        config.nuscenes.scene = choice.scene;
    }
    if (choice.sequence.empty()) return;
    if (config.reader != ReaderKind::kRadarScenes)
        throw ConfigError(DescriptionName(config) + ": --sequence " + choice.sequence +
                          ": chooses a RadarScenes sequence (reader radarscenes); this "
                          "description's reader is " +
                          reader);
    if (config.radarscenes.sequence_dir.empty())
        throw ConfigError(DescriptionName(config) + ": --sequence " + choice.sequence +
                          ": needs radarscenes.sequence_dir (a sequence beside the one chosen)");
    const bool number = std::all_of(choice.sequence.begin(), choice.sequence.end(),
                                    [](unsigned char c) { return std::isdigit(c); });
    const std::string name = number ? "sequence_" + choice.sequence : choice.sequence;
    const fs::path parent = RadarScenesSequenceDir(config).parent_path();
    const fs::path dir = parent / name;
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) {
        const std::vector<std::string> present = SequenceFolders(parent);
        std::string list;
        for (const std::string &s : present) list += (list.empty() ? "" : ", ") + s;
        const std::string closest = ClosestName(name, present, 2);
        throw ConfigError(DescriptionName(config) + ": --sequence " + choice.sequence + ": " +
                          dir.string() +
                          " is not a folder (the sequences beside "
                          "radarscenes.sequence_dir: " +
                          (list.empty() ? "none" : list) + ")" +
                          (closest.empty() ? "" : "; did you mean " + closest + "?"));
    }
    config.radarscenes.sequence_dir = dir.string();
}

void ApplyFormatLayout(DatasetConfig &config, bool mount_given) {
    try {
        if (config.reader == ReaderKind::kRadarScenes) {
            if (config.radarscenes.sensor_id == 0) config.radars = RadarScenesRadars(config);
            if (!mount_given)
                config.extrinsics.T_base_radar = config.radars.empty()
                                                     ? RadarScenesMount(config)
                                                     : config.radars.front().T_base_radar;
        }
        if (config.reader == ReaderKind::kNuScenes) {
            if (config.nuscenes.channel.empty()) config.radars = NuScenesRadars(config);
            if (!mount_given)
                config.extrinsics.T_base_radar = config.radars.empty()
                                                     ? NuScenesMount(config)
                                                     : config.radars.front().T_base_radar;
            const fs::path can_bus = fs::path(config.nuscenes.dataroot) / "can_bus" /
                                     (config.nuscenes.scene + "_ms_imu.json");
            std::error_code ec;
            if (config.imu.path.empty() && fs::exists(can_bus, ec)) {
                config.imu.path = can_bus.string();
                config.imu.format = ImuFileFormat::kNuScenesCanBus;
            }
        }
    } catch (const DatasetError &e) {
        const bool every_radar =
            (config.reader == ReaderKind::kRadarScenes && config.radarscenes.sensor_id == 0) ||
            (config.reader == ReaderKind::kNuScenes && config.nuscenes.channel.empty());
        throw ConfigError(config.config_path + ": " +
                          (every_radar ? "the data set's radars: " : "the radar's mount: ") +
                          e.what());
    }
}

}  // namespace dorado::io
