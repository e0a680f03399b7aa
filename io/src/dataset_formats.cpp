#include "dataset_formats.hpp"

#include "readers.hpp"

namespace dorado::io {

namespace fs = std::filesystem;

namespace {

// A folder relative to the YAML file, normalised (no "." / "..") and without a trailing separator:
// "data/sequence_105/" is "data/sequence_105", whose parent_path() is "data" (where RadarScenes
// keeps sensors.json), not the folder itself.
std::string ResolveDir(const std::string &path, const fs::path &base_dir) {
    if (path.empty()) return path;
    fs::path dir = fs::path(path).is_absolute() ? fs::path(path) : base_dir / path;
    dir = dir.lexically_normal();
    while (!dir.has_filename() && dir.has_relative_path()) dir = dir.parent_path();
    return dir.string();
}

}  // namespace

void ReadFormatSections(YamlSection &top, const fs::path &base_dir, DatasetConfig &config) {
    YamlSection rs = top.Child("radarscenes");
    config.radarscenes.sequence_dir = ResolveDir(rs.Get<std::string>("sequence_dir", ""), base_dir);
    config.radarscenes.sensor_id = rs.Get<int>("sensor_id", config.radarscenes.sensor_id);
    rs.RejectUnknownKeys();
    if (config.reader == ReaderKind::kRadarScenes) {
        if (config.radarscenes.sequence_dir.empty())
            top.Fail("radarscenes.sequence_dir", "is required for reader: radarscenes");
        if (config.radarscenes.sensor_id < 1 || config.radarscenes.sensor_id > 4)
            top.Fail("radarscenes.sensor_id", "must be 1, 2, 3 or 4 (RadarScenes' radars)");
    }
    YamlSection nu = top.Child("nuscenes");
    config.nuscenes.dataroot = ResolveDir(nu.Get<std::string>("dataroot", ""), base_dir);
    config.nuscenes.version = nu.Get<std::string>("version", "");
    config.nuscenes.scene = nu.Get<std::string>("scene", "");
    config.nuscenes.channel = nu.Get<std::string>("channel", "");
    nu.RejectUnknownKeys();
    if (config.reader == ReaderKind::kNuScenes) {
        for (const auto &[key, value] :
             {std::pair<const char *, const std::string &>{"dataroot", config.nuscenes.dataroot},
              {"version", config.nuscenes.version},
              {"scene", config.nuscenes.scene},
              {"channel", config.nuscenes.channel}}) {
            if (value.empty())
                top.Fail(std::string("nuscenes.") + key, "is required for reader: nuscenes");
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

void EmitFormatSection(YAML::Emitter &out, const DatasetConfig &config) {
    if (config.reader == ReaderKind::kRadarScenes) {
        out << YAML::Key << "radarscenes" << YAML::Value << YAML::BeginMap;
        out << YAML::Key << "sequence_dir" << YAML::Value << config.radarscenes.sequence_dir;
        out << YAML::Key << "sensor_id" << YAML::Value << config.radarscenes.sensor_id;
        out << YAML::EndMap;
    }
    if (config.reader == ReaderKind::kNuScenes) {
        out << YAML::Key << "nuscenes" << YAML::Value << YAML::BeginMap;
        out << YAML::Key << "dataroot" << YAML::Value << config.nuscenes.dataroot;
        out << YAML::Key << "version" << YAML::Value << config.nuscenes.version;
        out << YAML::Key << "scene" << YAML::Value << config.nuscenes.scene;
        out << YAML::Key << "channel" << YAML::Value << config.nuscenes.channel;
        out << YAML::EndMap;
    }
}

}  // namespace dorado::io
