#include "dorado/io/dataset_config.hpp"

#include "dorado/core/paper_mount.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <tuple>
#include <utility>

#include "dataset_formats.hpp"
#include "dorado/io/dataset_fields.hpp"
#include "dorado/io/field_yaml.hpp"
#include "dorado/io/yaml_section.hpp"
#include "readers.hpp"

namespace dorado::io {

namespace fs = std::filesystem;

namespace {

std::string ReaderName(ReaderKind reader) {
    return FormatValue(reader, ReaderKindChoices());
}

// The top-level sections that only some readers read: each reader's own (rosbag:, folder:,
// radarscenes:, nuscenes:), and the field map, which only the readers of PointCloud2 messages and
// scan files use (RadarScenes and nuScenes have their own fixed fields).
bool ReaderReads(ReaderKind reader, const std::string &section) {
    if (section == "fields") return reader == ReaderKind::kRosbag || reader == ReaderKind::kFolder;
    return section == ReaderName(reader);
}

// Fails, naming the file and the first key, on a key of a section the reader does not read (it
// would be ignored without a word: fields.doppler_sign with reader radarscenes, a folder: left over
// from another description), listing every such key. A null value is no value (as YamlSection).
void RejectKeysTheReaderDoesNotRead(const YAML::Node &root, const YamlSection &top,
                                    ReaderKind reader) {
    if (!root.IsMap()) return;
    std::vector<std::string> unused;
    for (const std::string section : {"rosbag", "folder", "radarscenes", "nuscenes", "fields"}) {
        if (ReaderReads(reader, section)) continue;
        const YAML::Node node = root[section];
        if (!node.IsDefined() || node.IsNull()) continue;
        if (!node.IsMap()) {
            unused.push_back(section);
            continue;
        }
        for (const auto &entry : node) {
            if (entry.second.IsDefined() && !entry.second.IsNull())
                unused.push_back(section + "." +
                                 (entry.first.IsScalar() ? entry.first.Scalar() : "?"));
        }
    }
    if (unused.empty()) return;
    std::string list;
    for (const auto &key : unused) list += (list.empty() ? "" : ", ") + key;
    top.Fail(unused.front(), std::string("is not used by reader: ") + ReaderName(reader) +
                                 " (remove it; the keys this reader does not use: " + list + ")");
}

// vehicle: the model's rules and each value's range.
void CheckVehicle(FieldReader &in, VehicleGeometry &vehicle) {
    if (vehicle.model == VehicleModel::kSkidSteer) {
        if (in.Has("vehicle.half_wheelbase_m") && vehicle.half_wheelbase_m != 0.0)
            in.Fail("vehicle.half_wheelbase_m",
                    "must be 0 (or absent) for model skid_steer: both ICR axes on one line");
        vehicle.half_wheelbase_m = 0.0;  // both ICR axes on the base origin's line
    }
    // m = 0 is allowed: both ICR axes on one line (a skid-steer base, the paper's Hugin).
    if (!(vehicle.half_wheelbase_m >= 0.0))
        in.Fail("vehicle.half_wheelbase_m", "must be a number >= 0");
    // model_noise: each a 1-sigma size, finite and >= 0 (0 = that constraint holds exactly).
    const KinematicModelNoise &noise = vehicle.model_noise;
    for (const auto &[key, value] :
         {std::pair<const char *, double>{"sigma_icr_x_m", noise.sigma_icr_x_m},
          {"rear_slip_rad_per_mps2", noise.rear_slip_rad_per_mps2},
          {"sigma_lateral_mps", noise.sigma_lateral_mps},
          {"sigma_vertical_mps", noise.sigma_vertical_mps},
          {"sigma_roll_rate_radps", noise.sigma_roll_rate_radps}}) {
        if (!(std::isfinite(value) && value >= 0.0))
            in.Fail(std::string("vehicle.model_noise.") + key,
                    "must be a number >= 0, got " + std::to_string(value));
    }
    // A prior's spread: > 0 (a large value is no prior).
    if (!(noise.angular_rate_prior_sigma_radps.allFinite() &&
          noise.angular_rate_prior_sigma_radps.minCoeff() > 0.0))
        in.Fail("vehicle.model_noise.angular_rate_prior_sigma_radps", "must be 3 numbers > 0");
    // absent: unknown (NaN), the ground-plane attitude is off
    if (in.Has("vehicle.base_height_m") &&
        !(vehicle.base_height_m > 0.0 && vehicle.base_height_m < 10.0))
        in.Fail("vehicle.base_height_m", "must be a height above the road in (0, 10) m");
    const VehicleVelocityPrior &prior = vehicle.velocity_prior;
    for (const auto &[key, value] :
         {std::pair<const char *, double>{"sigma_lateral_mps", prior.sigma_lateral_mps},
          {"sigma_vertical_mps", prior.sigma_vertical_mps}}) {
        if (!(std::isfinite(value) && value > 0.0))
            in.Fail(std::string("vehicle.velocity_prior.") + key,
                    "must be a number > 0, got " + std::to_string(value));
    }
    if (prior.enabled && vehicle.model == VehicleModel::kUnconstrained)
        in.Fail("vehicle.velocity_prior.enabled",
                "a ground vehicle's constraint: not with model unconstrained (hand-held, "
                "aerial, legged platforms move sideways and vertically)");
}

// radar: the sensor's 1-sigma noise and Doppler ambiguity, each finite, >= 0 and below a bound.
void CheckRadarSensor(FieldReader &in, const RadarSensorModel &radar) {
    for (const auto &[key, value, upper] :
         {std::tuple<const char *, double, double>{"range_sigma_m", radar.range_sigma_m, 100.0},
          {"azimuth_sigma_deg", radar.azimuth_sigma_deg, 20.0},
          {"elevation_sigma_deg", radar.elevation_sigma_deg, 20.0},
          {"doppler_unambiguous_mps", radar.doppler_unambiguous_mps, 1000.0}}) {
        if (!(std::isfinite(value) && value >= 0.0 && value < upper))
            in.Fail(std::string("radar.") + key, "must be a number in [0, " +
                                                     std::to_string(upper) + "), got " +
                                                     std::to_string(value));
    }
}

// The checks of the values the field list read (ranges, the keys each reader needs), each naming
// its key.
void CheckFields(FieldReader &in, DatasetConfig &config) {
    if (!(std::abs(config.rosbag.radar_trigger_offset_s) < 1.0))
        in.Fail("rosbag.radar_trigger_offset_s", "must be a number of seconds in (-1, 1)");
    if (config.reader == ReaderKind::kRosbag) {
        if (config.rosbag.path.empty()) in.Fail("rosbag.path", "is required for reader: rosbag");
        if (config.rosbag.radar_topic.empty()) in.Fail("rosbag.radar_topic", "must not be empty");
    }
    if (config.reader == ReaderKind::kFolder) {
        if (config.folder.scans_dir.empty())
            in.Fail("folder.scans_dir", "is required for reader: folder");
        if (config.folder.timestamps_file.empty())
            in.Fail("folder.timestamps_file", "is required for reader: folder");
        if (config.folder.extension != ".bin" && config.folder.extension != ".pcd")
            in.Fail("folder.extension", "must be .bin or .pcd");
        if (config.folder.extension == ".bin" && config.folder.columns.empty())
            in.Fail("folder.columns", "is required for .bin scans (one name per float32 column)");
    }
    CheckFormatSections(in, config);
    const FieldMap &map = config.fields;
    if (map.doppler_sign != 1.0 && map.doppler_sign != -1.0)
        in.Fail("fields.doppler_sign", "must be 1 or -1");
    for (const auto *required : {&map.x, &map.y, &map.z, &map.doppler})
        if (required->empty()) in.Fail("fields", "x, y, z and doppler need a field name");
    if (config.ground_truth.format == TrajectoryFormat::kKitti &&
        !config.ground_truth.path.empty() && config.ground_truth.kitti_times_path.empty())
        in.Fail("ground_truth.kitti_times", "is required for format: kitti");
    if (config.reader == ReaderKind::kRosbag && !config.imu.path.empty())
        in.Fail("imu.path",
                "is not read with reader: rosbag (a recording's IMU is rosbag.imu_topic)");
    CheckVehicle(in, config.vehicle);
    CheckRadarSensor(in, config.radar);
}

// `radars:` (reader folder): each radar's keys are RadarStream's field list, its paths taken from
// @p base_dir. A misspelt key is named before the keys it leaves missing.
void ReadRadars(const YAML::Node &root, FieldReader &in, const std::string &yaml_path,
                const std::string &base_dir, DatasetConfig &config) {
    const YAML::Node list = root["radars"];
    if (!list.IsSequence()) in.Fail("radars", "must be a list of radars");
    if (config.reader != ReaderKind::kFolder)
        in.Fail("radars",
                "needs reader: folder (readers radarscenes and nuscenes list their "
                "radars from the data set's own files)");
    for (std::size_t k = 0; k < list.size(); ++k) {
        const std::string where = "radars[" + std::to_string(k) + "]";
        FieldReader item(YamlSection(list[k], yaml_path, where), base_dir);
        RadarStream radar;
        radar.name = "radar" + std::to_string(k);
        VisitFields(radar, item);
        item.RejectUnknownKeys();
        if (radar.scans_dir.empty()) item.Fail("scans_dir", "is required");
        if (radar.timestamps_file.empty()) item.Fail("timestamps_file", "is required");
        if (!item.Has("T_base_radar")) item.Fail("T_base_radar", "is required (the mount)");
        for (const auto &path : item.paths_read())
            config.inputs.push_back({where + "." + path.key, path.written, path.resolved});
        config.radars.push_back(radar);
    }
}

// --scene / --sequence over the description's scene or sequence (dataset_formats.cpp), a sequence
// looked for beside radarscenes.sequence_dir as --data or data_dir: resolved it. The chosen folder
// replaces the description's among the inputs RequireInputs checks.
void ApplyChoice(DatasetConfig &config, const DatasetChoice &choice) {
    try {
        ApplyDatasetChoice(config, choice);
    } catch (const ConfigError &e) {
        // No folder beside a relative sequence_dir that is not there: say where it was taken from.
        std::error_code ec;
        for (const DatasetInput &input : config.inputs) {
            if (input.key != "radarscenes.sequence_dir" || fs::exists(input.path, ec) ||
                fs::path(input.written).is_absolute())
                continue;
            throw ConfigError(std::string(e.what()) + " (radarscenes.sequence_dir " +
                              input.written + " is a relative path " + DescribePathBase(config) +
                              "; pass --data DIR with the folder that holds it)");
        }
        throw;
    }
    for (DatasetInput &input : config.inputs)
        if (input.key == "radarscenes.sequence_dir") input.path = config.radarscenes.sequence_dir;
}

// `reader:` absent: the default (rosbag) only for a description with a `rosbag:` section;
// otherwise it is asked for by name, with the reader whose section the description has.
void RequireReader(const YAML::Node &root, FieldReader &in) {
    if (in.Has("reader") || in.Has("rosbag")) return;
    std::string hint;
    for (const char *section : {"folder", "radarscenes", "nuscenes"}) {
        if (root.IsMap() && root[section].IsDefined() && !root[section].IsNull()) {
            hint = std::string(" (this description has a ") + section +
                   ": section: add reader: " + section + ")";
            break;
        }
    }
    in.Fail("reader", "is required: rosbag, folder, radarscenes or nuscenes" + hint);
}

// The reader of the description's fields: after data_dir (the first path of the field list),
// the relative paths are taken from the data folder.
struct DescriptionReader {
    FieldReader &in;
    std::string data_option;      // --data DIR, absolute; empty: none
    std::string description_dir;  // the description's folder, absolute
    DatasetConfig &config;

    template <typename... Args>
    void operator()(const char *key, Args &&...args) {
        in(key, std::forward<Args>(args)...);
    }
    void operator()(const char *key, std::string &member, PathField path, const char *doc) {
        in(key, member, path, doc);
        if (&member != &config.data_dir) return;
        config.path_base = !data_option.empty() ? PathBase::kDataOption
                           : !member.empty()    ? PathBase::kDataDirKey
                                                : PathBase::kDescriptionFolder;
        config.path_base_dir = !data_option.empty() ? data_option
                               : !member.empty()    ? member
                                                    : description_dir;
        in.set_base_dir(config.path_base_dir);
    }
};

// The fields a description of @p reader writes: not the sections other readers read (the reader
// refuses them), not an unknown value (NaN: vehicle.base_height_m).
struct WrittenFields {
    ReaderKind reader;
    FieldWriter &writer;

    bool Keeps(const std::string &key) const {
        const std::string section = key.substr(0, key.find('.'));
        for (const char *only : {"rosbag", "folder", "radarscenes", "nuscenes", "fields"})
            if (section == only) return ReaderReads(reader, section);
        return true;
    }
    template <typename T>
    void operator()(const char *key, T &member, const char *doc) const {
        if constexpr (std::is_same_v<T, double>)
            if (std::isnan(member)) return;
        if (Keeps(key)) writer(key, member, doc);
    }
    template <typename T, typename Extra>
    void operator()(const char *key, T &member, const Extra &extra, const char *doc) const {
        if (Keeps(key)) writer(key, member, extra, doc);
    }
};

// The native readers' root key and where --data points for them.
const char *RootKey(const DatasetConfig &config) {
    return config.reader == ReaderKind::kNuScenes      ? "nuscenes.dataroot"
           : config.reader == ReaderKind::kRadarScenes ? "radarscenes.sequence_dir"
                                                       : "";
}

// --data DIR for the data sets' own layouts is the release's root, whatever the description's
// root key says: nuScenes' dataroot (the folder of v1.0-*/, sweeps/, can_bus/) and RadarScenes'
// folder that holds data/sequence_N (or DIR/sequence_N itself), N from the description's
// sequence_dir (--sequence then picks another beside it). The key's relative path taken from DIR
// is kept when only it holds the data.
void UseDataOptionAsRoot(DatasetConfig &config, const std::string &data_option) {
    std::error_code ec;
    std::string resolved;
    if (config.reader == ReaderKind::kNuScenes) {
        const bool joined_holds =
            fs::is_directory(fs::path(config.nuscenes.dataroot) / config.nuscenes.version, ec);
        const bool root_holds =
            fs::is_directory(fs::path(data_option) / config.nuscenes.version, ec);
        if (joined_holds && !root_holds) return;
        resolved = config.nuscenes.dataroot = data_option;
    } else if (config.reader == ReaderKind::kRadarScenes &&
               !config.radarscenes.sequence_dir.empty()) {
        const fs::path name = RadarScenesSequenceDir(config).filename();
        const fs::path in_data = fs::path(data_option) / "data" / name,
                       beside = fs::path(data_option) / name;
        if (fs::is_directory(in_data, ec))
            resolved = in_data.string();
        else if (fs::is_directory(beside, ec))
            resolved = beside.string();
        else if (fs::is_directory(config.radarscenes.sequence_dir, ec))
            return;
        else
            resolved = in_data.string();
        config.radarscenes.sequence_dir = resolved;
    } else {
        return;
    }
    for (DatasetInput &input : config.inputs)
        if (input.key == RootKey(config)) input.path = resolved;
}

// For an error of a data set's own layout: the root key as written and resolved, and from where.
std::string RootKeyHint(const DatasetConfig &config) {
    const std::string key = RootKey(config);
    for (const DatasetInput &input : config.inputs) {
        if (input.key != key) continue;
        const std::string base = config.path_base == PathBase::kDataOption
                                     ? "--data " + config.path_base_dir + " (the data set's root)"
                                 : fs::path(input.written).is_absolute()
                                     ? std::string("an absolute path")
                                     : "a relative path " + DescribePathBase(config);
        return " (key '" + key + "': written " + input.written + ", resolved " + input.path + ", " +
               base + "; pass --data DIR with the data set's root: " +
               (config.reader == ReaderKind::kNuScenes
                    ? "the folder that holds " + config.nuscenes.version + "/ and sweeps/"
                    : std::string("the folder that holds data/sequence_N")) +
               ")";
    }
    return "";
}

}  // namespace

DatasetConfig ForRadar(const DatasetConfig &config, std::size_t index) {
    const RadarStream &radar = config.radars.at(index);
    DatasetConfig one = config;
    one.name = config.name + "/" + radar.name;
    one.folder.scans_dir = radar.scans_dir;
    one.folder.timestamps_file = radar.timestamps_file;
    if (config.reader == ReaderKind::kRadarScenes)
        one.radarscenes.sensor_id = radar.radarscenes_sensor_id;
    if (config.reader == ReaderKind::kNuScenes) one.nuscenes.channel = radar.nuscenes_channel;
    one.extrinsics.T_base_radar = radar.T_base_radar;
    one.radars.clear();
    return one;
}

DatasetConfig LoadDatasetConfig(const std::string &yaml_path, const std::string &data_dir,
                                const DatasetChoice &choice) {
    const std::string description_dir = fs::absolute(yaml_path).parent_path().string();
    std::string data_option;
    if (!data_dir.empty()) {
        std::error_code ec;
        if (!fs::is_directory(data_dir, ec))
            throw ConfigError("--data " + data_dir + ": no such folder (the folder that " +
                              yaml_path + "'s relative paths are taken from)");
        data_option = fs::absolute(data_dir).lexically_normal().string();
        while (!fs::path(data_option).has_filename() && fs::path(data_option).has_relative_path())
            data_option = fs::path(data_option).parent_path().string();
    }
    const YAML::Node root = LoadYamlFile(yaml_path);
    FieldReader in(YamlSection(root, yaml_path), description_dir);
    DatasetConfig config;
    config.config_path = yaml_path;
    config.name = fs::path(yaml_path).stem().string();
    RequireReader(root, in);
    in("reader", config.reader, ReaderKindChoices(), "");
    RejectKeysTheReaderDoesNotRead(root, in.Section(""), config.reader);
    VisitFields(config, DescriptionReader{in, data_option, description_dir, config});
    const bool has_radars = in.Has("radars");
    in.RejectUnknownKeys();  // before the radars' and the fields' checks of missing keys
    for (const auto &path : in.paths_read())
        if (path.key != "data_dir")
            config.inputs.push_back({path.key, path.written, path.resolved});
    if (has_radars) ReadRadars(root, in, yaml_path, config.path_base_dir, config);
    if (!data_option.empty()) UseDataOptionAsRoot(config, data_option);
    ApplyChoice(config, choice);  // over the paths as resolved
    CheckFields(in, config);
    const bool mount_given = in.Has("extrinsics.T_base_radar");
    try {
        ApplyFormatLayout(config, mount_given);  // the data set's own radars
    } catch (const ConfigError &e) {
        throw ConfigError(std::string(e.what()) + RootKeyHint(config));
    }
    config.mount_source =
        mount_given || has_radars ? MountSource::kGiven
        : config.reader == ReaderKind::kRadarScenes || config.reader == ReaderKind::kNuScenes
            ? MountSource::kDataSet
            : MountSource::kIdentityAssumed;
    return config;
}

std::string DescribePathBase(const DatasetConfig &config) {
    switch (config.path_base) {
        case PathBase::kDataOption:
            return "taken from --data " + config.path_base_dir;
        case PathBase::kDataDirKey:
            return "taken from the description's data_dir: " + config.path_base_dir;
        case PathBase::kDescriptionFolder:
            return "taken from the description's folder " + config.path_base_dir +
                   " (it has no data_dir: and no --data DIR was given)";
    }
    return "";
}

void RequireInputs(const DatasetConfig &config) {
    for (const DatasetInput &input : config.inputs) {
        std::error_code ec;
        if (fs::exists(input.path, ec)) continue;
        const std::string where =
            config.config_path.empty() ? "the description" : config.config_path;
        if (config.path_base == PathBase::kDataOption && input.key == RootKey(config))
            throw ConfigError(where + ": key '" + input.key + "': " + input.path +
                              ": no such file or folder (written " + input.written + "; --data " +
                              config.path_base_dir +
                              " is taken as the data set's root: give the folder that holds " +
                              (config.reader == ReaderKind::kNuScenes
                                   ? config.nuscenes.version + "/ and sweeps/"
                                   : std::string("data/sequence_N")) +
                              ")");
        if (fs::path(input.written).is_absolute())
            throw ConfigError(where + ": key '" + input.key + "': " + input.path +
                              ": no such file or folder (an absolute path: fix the key)");
        throw ConfigError(where + ": key '" + input.key + "': " + input.path +
                          ": no such file or folder (written " + input.written +
                          ", a relative path " + DescribePathBase(config) +
                          "; pass --data DIR with the folder that holds " + input.written +
                          ", or write an absolute path)");
    }
}

DatasetConfig ResolveDataset(const std::string &argument, const std::string &data_dir,
                             const DatasetChoice &choice) {
    const fs::path path(argument);
    std::error_code ec;
    const auto description = [&](const std::string &yaml) {
        DatasetConfig config = LoadDatasetConfig(yaml, data_dir, choice);
        RequireInputs(config);
        return config;
    };
    if (fs::is_directory(path, ec)) {
        const fs::path in_folder = path / "dataset.yaml";
        if (fs::exists(in_folder)) return description(in_folder.string());
        if (!fs::exists(path / "metadata.yaml")) {
            throw ConfigError(argument +
                              ": a folder without dataset.yaml or metadata.yaml (rosbag2); pass a "
                              "dataset description (.yaml), a .bag, .db3 or .mcap");
        }
    }
    if (!fs::exists(path, ec)) throw ConfigError(argument + ": no such file");
    const std::string ext = path.extension().string();
    if (ext == ".yaml" || ext == ".yml") return description(argument);
    if (!data_dir.empty())
        throw ConfigError("--data " + data_dir + ": only for a dataset description (.yaml); " +
                          argument + " is a recording");
    // A recording: ROS1 .bag, rosbag2 folder, .db3 or .mcap (the reader tells them by their bytes).
    if (ext == ".bag" || ext == ".db3" || ext == ".mcap" || fs::is_directory(path, ec)) {
        // The paper's Hugin dataset layout: radar PointCloud2 on /hugin_raf_1/radar_data, and
        // the mount of the paper's launch file (configs/hugin.yaml derives it).
        DatasetConfig config;
        const PaperMount mount = MountFromPaperParameters(PaperMountParameters{});
        config.extrinsics = mount.extrinsics;
        config.vehicle.half_wheelbase_m = mount.half_wheelbase_m;
        config.vehicle.base_height_m = mount.base_height_m;
        config.name = (path.has_filename() ? path : path.parent_path()).stem().string();
        config.reader = ReaderKind::kRosbag;
        config.mount_source = MountSource::kHuginDefault;
        config.rosbag.path = argument;
        ApplyDatasetChoice(config, choice);  // refused: a recording has no scenes
        return config;
    }
    throw ConfigError(argument +
                      ": not a dataset (expected a .yaml description, a .bag, .db3 or .mcap "
                      "recording, or a folder with dataset.yaml or metadata.yaml)");
}

std::string DatasetConfigToYaml(const DatasetConfig &config) {
    DatasetConfig copy = config;
    FieldWriter writer;
    VisitFields(copy, WrittenFields{copy.reader, writer});
    if (!copy.radars.empty() && copy.reader == ReaderKind::kFolder) {  // the others': their files
        std::vector<std::string> items;
        for (RadarStream &radar : copy.radars) {
            FieldWriter item;
            VisitFields(radar, item);
            items.push_back(item.text());
        }
        writer.AddList("radars", items, "several radars (reader folder)");
    }
    return writer.text();
}

std::vector<FieldRow> DatasetConfigFields() {
    auto rows = ListFields(DatasetConfig{});
    for (const auto &row : ListFields(RadarStream{}, "radars[].")) rows.push_back(row);
    return rows;
}

}  // namespace dorado::io
