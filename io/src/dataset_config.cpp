#include "dorado/io/dataset_config.hpp"

#include "dorado/core/lie.hpp"
#include "dorado/core/paper_mount.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>

#include "dataset_formats.hpp"
#include "dorado/io/yaml_section.hpp"

namespace dorado::io {

namespace fs = std::filesystem;

namespace {

const char *ReaderName(ReaderKind reader) {
    switch (reader) {
        case ReaderKind::kRosbag:
            return "rosbag";
        case ReaderKind::kFolder:
            return "folder";
        case ReaderKind::kRadarScenes:
            return "radarscenes";
        case ReaderKind::kNuScenes:
            return "nuscenes";
    }
    return "rosbag";
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

std::string ResolvePath(const std::string &path, const fs::path &base_dir) {
    if (path.empty() || fs::path(path).is_absolute()) return path;
    return (base_dir / path).lexically_normal().string();
}

Eigen::Isometry3d ReadTransform(YamlSection section) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    section.ReadVector3("translation_m", t);
    T.translation() = t;
    const bool has_rpy = section.Has("rotation_rpy_deg");
    const bool has_q = section.Has("quaternion_xyzw");
    if (has_rpy && has_q)
        section.Fail("rotation_rpy_deg",
                     "give either rotation_rpy_deg or quaternion_xyzw, not both");
    if (has_rpy) {
        Eigen::Vector3d rpy = Eigen::Vector3d::Zero();
        section.ReadVector3("rotation_rpy_deg", rpy);
        T.linear() = RotationFromRollPitchYaw(rpy * M_PI / 180.0);
    }
    if (has_q) {
        const auto q = section.Get<std::vector<double>>("quaternion_xyzw", {});
        if (q.size() != 4) section.Fail("quaternion_xyzw", "must have 4 values");
        const Eigen::Quaterniond quat(q[3], q[0], q[1], q[2]);
        if (std::abs(quat.norm() - 1.0) > 1e-3) section.Fail("quaternion_xyzw", "must have norm 1");
        T.linear() = quat.normalized().toRotationMatrix();
    }
    if (!T.matrix().allFinite()) section.Fail("", "is not finite");
    section.RejectUnknownKeys();
    return T;
}

FieldMap ReadFieldMap(YamlSection section) {
    FieldMap map;
    map.x = section.Get<std::string>("x", map.x);
    map.y = section.Get<std::string>("y", map.y);
    map.z = section.Get<std::string>("z", map.z);
    map.range = section.Get<std::string>("range", map.range);
    map.azimuth = section.Get<std::string>("azimuth", map.azimuth);
    map.elevation = section.Get<std::string>("elevation", map.elevation);
    map.power = section.Get<std::string>("power", map.power);
    map.doppler = section.Get<std::string>("doppler", map.doppler);
    map.doppler_sign = section.Get<double>("doppler_sign", map.doppler_sign);
    if (map.doppler_sign != 1.0 && map.doppler_sign != -1.0) {
        section.Fail("doppler_sign", "must be 1 or -1");
    }
    for (const auto *required : {&map.x, &map.y, &map.z, &map.doppler}) {
        if (required->empty()) section.Fail("", "x, y, z and doppler need a field name");
    }
    section.RejectUnknownKeys();
    return map;
}

const char *FormatName(TrajectoryFormat format) {
    switch (format) {
        case TrajectoryFormat::kTum:
            return "tum";
        case TrajectoryFormat::kKitti:
            return "kitti";
        case TrajectoryFormat::kPaperCsv:
            return "paper_csv";
    }
    return "tum";
}

// imu.format's names: the one spelling for reading and writing.
const std::vector<std::pair<std::string, ImuFileFormat>> kImuFileFormats = {
    {"nuscenes_can_bus", ImuFileFormat::kNuScenesCanBus}};

const std::string &ImuFormatName(ImuFileFormat format) {
    for (const auto &[name, value] : kImuFileFormats)
        if (value == format) return name;
    return kImuFileFormats.front().first;
}

// vehicle.model_noise: each a 1-sigma size, finite and >= 0 (0 = that constraint holds exactly).
KinematicModelNoise ReadModelNoise(YamlSection section) {
    KinematicModelNoise noise;
    const auto read = [&section](const char *key, double &value) {
        value = section.Get<double>(key, value);
        if (!(std::isfinite(value) && value >= 0.0))
            section.Fail(key, "must be a number >= 0, got " + std::to_string(value));
    };
    read("sigma_icr_x_m", noise.sigma_icr_x_m);
    read("rear_slip_rad_per_mps2", noise.rear_slip_rad_per_mps2);
    read("sigma_lateral_mps", noise.sigma_lateral_mps);
    read("sigma_vertical_mps", noise.sigma_vertical_mps);
    read("sigma_roll_rate_radps", noise.sigma_roll_rate_radps);
    // A prior's spread: > 0 (a large value is no prior).
    section.ReadVector3("angular_rate_prior_sigma_radps", noise.angular_rate_prior_sigma_radps);
    if (!(noise.angular_rate_prior_sigma_radps.allFinite() &&
          noise.angular_rate_prior_sigma_radps.minCoeff() > 0.0))
        section.Fail("angular_rate_prior_sigma_radps", "must be 3 numbers > 0");
    section.RejectUnknownKeys();
    return noise;
}

// vehicle.velocity_prior: enabled, and the two spreads (> 0).
VehicleVelocityPrior ReadVelocityPrior(YamlSection section) {
    VehicleVelocityPrior prior;
    prior.enabled = section.Get<bool>("enabled", prior.enabled);
    const auto read = [&section](const char *key, double &value) {
        value = section.Get<double>(key, value);
        if (!(std::isfinite(value) && value > 0.0))
            section.Fail(key, "must be a number > 0, got " + std::to_string(value));
    };
    read("sigma_lateral_mps", prior.sigma_lateral_mps);
    read("sigma_vertical_mps", prior.sigma_vertical_mps);
    section.RejectUnknownKeys();
    return prior;
}

// radar: the sensor's 1-sigma noise and Doppler ambiguity, each finite and >= 0.
RadarSensorModel ReadRadarSensor(YamlSection section) {
    RadarSensorModel radar;
    const auto read = [&section](const char *key, double &value, double upper) {
        value = section.Get<double>(key, value);
        if (!(std::isfinite(value) && value >= 0.0 && value < upper))
            section.Fail(key, "must be a number in [0, " + std::to_string(upper) + "), got " +
                                  std::to_string(value));
    };
    read("range_sigma_m", radar.range_sigma_m, 100.0);
    read("azimuth_sigma_deg", radar.azimuth_sigma_deg, 20.0);
    read("elevation_sigma_deg", radar.elevation_sigma_deg, 20.0);
    read("doppler_unambiguous_mps", radar.doppler_unambiguous_mps, 1000.0);
    section.ReadEnum("geometry", radar.geometry,
                     {{"auto", ScanGeometry::kAuto},
                      {"3d", ScanGeometry::k3d},
                      {"planar", ScanGeometry::kPlanar}});
    section.RejectUnknownKeys();
    return radar;
}

}  // namespace

DatasetConfig ForRadar(const DatasetConfig &config, std::size_t index) {
    const RadarStream &radar = config.radars.at(index);
    DatasetConfig one = config;
    one.name = config.name + "/" + radar.name;
    one.folder.scans_dir = radar.scans_dir;
    one.folder.timestamps_file = radar.timestamps_file;
    one.extrinsics.T_base_radar = radar.T_base_radar;
    one.radars.clear();
    return one;
}

DatasetConfig LoadDatasetConfig(const std::string &yaml_path) {
    const fs::path base_dir = fs::absolute(yaml_path).parent_path();
    const YAML::Node root = LoadYamlFile(yaml_path);
    YamlSection top(root, yaml_path);
    DatasetConfig config;
    config.config_path = yaml_path;
    config.name = top.Get<std::string>("name", fs::path(yaml_path).stem().string());

    top.ReadEnum("reader", config.reader,
                 {{"rosbag", ReaderKind::kRosbag},
                  {"folder", ReaderKind::kFolder},
                  {"radarscenes", ReaderKind::kRadarScenes},
                  {"nuscenes", ReaderKind::kNuScenes}});
    RejectKeysTheReaderDoesNotRead(root, top, config.reader);

    YamlSection rosbag = top.Child("rosbag");
    config.rosbag.path = ResolvePath(rosbag.Get<std::string>("path", ""), base_dir);
    config.rosbag.radar_topic = rosbag.Get<std::string>("radar_topic", config.rosbag.radar_topic);
    config.rosbag.imu_topic = rosbag.Get<std::string>("imu_topic", "");
    config.rosbag.ground_truth_topic = rosbag.Get<std::string>("ground_truth_topic", "");
    config.rosbag.radar_trigger_topic = rosbag.Get<std::string>("radar_trigger_topic", "");
    config.rosbag.radar_trigger_offset_s = rosbag.Get<double>("radar_trigger_offset_s", 0.0);
    if (!(std::abs(config.rosbag.radar_trigger_offset_s) < 1.0))
        rosbag.Fail("radar_trigger_offset_s", "must be a number of seconds in (-1, 1)");
    rosbag.RejectUnknownKeys();
    if (config.reader == ReaderKind::kRosbag) {
        if (config.rosbag.path.empty()) top.Fail("rosbag.path", "is required for reader: rosbag");
        if (config.rosbag.radar_topic.empty()) top.Fail("rosbag.radar_topic", "must not be empty");
    }

    YamlSection folder = top.Child("folder");
    config.folder.scans_dir = ResolvePath(folder.Get<std::string>("scans_dir", ""), base_dir);
    config.folder.extension = folder.Get<std::string>("extension", config.folder.extension);
    config.folder.timestamps_file =
        ResolvePath(folder.Get<std::string>("timestamps_file", ""), base_dir);
    config.folder.columns = folder.Get<std::vector<std::string>>("columns", {});
    folder.RejectUnknownKeys();
    if (config.reader == ReaderKind::kFolder) {
        if (config.folder.scans_dir.empty())
            top.Fail("folder.scans_dir", "is required for reader: folder");
        if (config.folder.timestamps_file.empty())
            top.Fail("folder.timestamps_file", "is required for reader: folder");
        if (config.folder.extension != ".bin" && config.folder.extension != ".pcd") {
            top.Fail("folder.extension", "must be .bin or .pcd");
        }
        if (config.folder.extension == ".bin" && config.folder.columns.empty()) {
            top.Fail("folder.columns", "is required for .bin scans (one name per float32 column)");
        }
    }

    ReadFormatSections(top, base_dir, config);

    config.fields = ReadFieldMap(top.Child("fields"));

    YamlSection gt = top.Child("ground_truth");
    config.ground_truth.path = ResolvePath(gt.Get<std::string>("path", ""), base_dir);
    gt.ReadEnum("format", config.ground_truth.format,
                {{"tum", TrajectoryFormat::kTum},
                 {"kitti", TrajectoryFormat::kKitti},
                 {"paper_csv", TrajectoryFormat::kPaperCsv}});
    config.ground_truth.kitti_times_path =
        ResolvePath(gt.Get<std::string>("kitti_times", ""), base_dir);
    gt.RejectUnknownKeys();
    if (config.ground_truth.format == TrajectoryFormat::kKitti &&
        !config.ground_truth.path.empty() && config.ground_truth.kitti_times_path.empty()) {
        top.Fail("ground_truth.kitti_times", "is required for format: kitti");
    }

    YamlSection imu = top.Child("imu");
    config.imu.path = ResolvePath(imu.Get<std::string>("path", ""), base_dir);
    imu.ReadEnum("format", config.imu.format, kImuFileFormats);
    imu.RejectUnknownKeys();
    if (config.reader == ReaderKind::kRosbag && !config.imu.path.empty())
        top.Fail("imu.path",
                 "is not read with reader: rosbag (a recording's IMU is rosbag.imu_topic)");

    YamlSection extrinsics = top.Child("extrinsics");
    config.extrinsics.T_base_radar = ReadTransform(extrinsics.Child("T_base_radar"));
    if (!extrinsics.Has("T_base_radar")) ApplyFormatMount(config);  // the data set's own
    config.extrinsics.T_base_imu = ReadTransform(extrinsics.Child("T_base_imu"));
    extrinsics.RejectUnknownKeys();

    YamlSection vehicle = top.Child("vehicle");
    vehicle.ReadEnum("model", config.vehicle.model,
                     {{"ackermann", VehicleModel::kAckermann},
                      {"skid_steer", VehicleModel::kSkidSteer},
                      {"unconstrained", VehicleModel::kUnconstrained}});
    if (config.vehicle.model == VehicleModel::kSkidSteer) {
        config.vehicle.half_wheelbase_m = 0.0;  // both ICR axes on the base origin's line
        if (vehicle.Has("half_wheelbase_m") && vehicle.Get<double>("half_wheelbase_m", 0.0) != 0.0)
            vehicle.Fail("half_wheelbase_m",
                         "must be 0 (or absent) for model skid_steer: both ICR axes on one line");
    }
    // m = 0 is allowed: both ICR axes on one line (a skid-steer base, the paper's Hugin).
    config.vehicle.half_wheelbase_m =
        vehicle.Get<double>("half_wheelbase_m", config.vehicle.half_wheelbase_m);
    if (!(config.vehicle.half_wheelbase_m >= 0.0))
        vehicle.Fail("half_wheelbase_m", "must be a number >= 0");
    config.vehicle.model_noise = ReadModelNoise(vehicle.Child("model_noise"));
    if (vehicle.Has("base_height_m")) {  // absent: unknown, the ground-plane attitude is off
        config.vehicle.base_height_m = vehicle.Get<double>("base_height_m", 0.0);
        if (!(config.vehicle.base_height_m > 0.0 && config.vehicle.base_height_m < 10.0))
            vehicle.Fail("base_height_m", "must be a height above the road in (0, 10) m");
    }
    config.vehicle.velocity_prior = ReadVelocityPrior(vehicle.Child("velocity_prior"));
    if (config.vehicle.velocity_prior.enabled &&
        config.vehicle.model == VehicleModel::kUnconstrained)
        vehicle.Fail("velocity_prior.enabled",
                     "a ground vehicle's constraint: not with model unconstrained (hand-held, "
                     "aerial, legged platforms move sideways and vertically)");
    vehicle.RejectUnknownKeys();
    config.radar = ReadRadarSensor(top.Child("radar"));

    if (top.Has("radars")) {  // several radars: a list of {name, scans_dir, timestamps_file,
                              // T_base_radar}
        const YAML::Node list = root["radars"];
        if (!list.IsSequence()) top.Fail("radars", "must be a list of radars");
        if (config.reader != ReaderKind::kFolder) top.Fail("radars", "needs reader: folder");
        for (std::size_t k = 0; k < list.size(); ++k) {
            YamlSection item(list[k], yaml_path, "radars[" + std::to_string(k) + "]");
            RadarStream radar;
            radar.name = item.Get<std::string>("name", "radar" + std::to_string(k));
            radar.scans_dir = ResolvePath(item.Get<std::string>("scans_dir", ""), base_dir);
            radar.timestamps_file =
                ResolvePath(item.Get<std::string>("timestamps_file", ""), base_dir);
            if (radar.scans_dir.empty()) item.Fail("scans_dir", "is required");
            if (radar.timestamps_file.empty()) item.Fail("timestamps_file", "is required");
            if (!item.Has("T_base_radar")) item.Fail("T_base_radar", "is required (the mount)");
            radar.T_base_radar = ReadTransform(item.Child("T_base_radar"));
            item.RejectUnknownKeys();
            config.radars.push_back(radar);
        }
    }

    top.RejectUnknownKeys();
    return config;
}

DatasetConfig ResolveDataset(const std::string &argument) {
    const fs::path path(argument);
    std::error_code ec;
    if (fs::is_directory(path, ec)) {
        const fs::path description = path / "dataset.yaml";
        if (fs::exists(description)) return LoadDatasetConfig(description.string());
        if (!fs::exists(path / "metadata.yaml")) {
            throw ConfigError(argument +
                              ": a folder without dataset.yaml or metadata.yaml (rosbag2); pass a "
                              "dataset description (.yaml), a .bag, .db3 or .mcap");
        }
    }
    if (!fs::exists(path, ec)) throw ConfigError(argument + ": no such file");
    const std::string ext = path.extension().string();
    if (ext == ".yaml" || ext == ".yml") return LoadDatasetConfig(argument);
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
        config.rosbag.path = argument;
        return config;
    }
    throw ConfigError(argument +
                      ": not a dataset (expected a .yaml description, a .bag, .db3 or .mcap "
                      "recording, or a folder with dataset.yaml or metadata.yaml)");
}

namespace {

// `key: [x, y, z]`, the form ReadVector3 reads back.
void EmitVector3(YAML::Emitter &out, const char *key, const Eigen::Vector3d &v) {
    out << YAML::Key << key << YAML::Value << YAML::Flow
        << std::vector<double>{v.x(), v.y(), v.z()};
}

void EmitTransform(YAML::Emitter &out, const char *name, const Eigen::Isometry3d &T) {
    const Eigen::Quaterniond q(T.linear());
    out << YAML::Key << name << YAML::Value << YAML::BeginMap;
    EmitVector3(out, "translation_m", T.translation());
    out << YAML::Key << "quaternion_xyzw" << YAML::Value << YAML::Flow
        << std::vector<double>{q.x(), q.y(), q.z(), q.w()};
    out << YAML::EndMap;
}

// `fields:`, for the readers that read it (ReaderReads).
void EmitFieldMap(YAML::Emitter &out, const DatasetConfig &config) {
    if (!ReaderReads(config.reader, "fields")) return;
    const FieldMap &f = config.fields;
    out << YAML::Key << "fields" << YAML::Value << YAML::BeginMap;
    for (const auto &[key, value] :
         std::vector<std::pair<const char *, std::string>>{{"x", f.x},
                                                           {"y", f.y},
                                                           {"z", f.z},
                                                           {"range", f.range},
                                                           {"azimuth", f.azimuth},
                                                           {"elevation", f.elevation},
                                                           {"power", f.power},
                                                           {"doppler", f.doppler}}) {
        out << YAML::Key << key << YAML::Value << value;
    }
    out << YAML::Key << "doppler_sign" << YAML::Value << f.doppler_sign;
    out << YAML::EndMap;
}

}  // namespace

std::string DatasetConfigToYaml(const DatasetConfig &config) {
    YAML::Emitter out;
    out.SetDoublePrecision(17);
    out << YAML::BeginMap;
    out << YAML::Key << "name" << YAML::Value << config.name;
    out << YAML::Key << "reader" << YAML::Value << ReaderName(config.reader);
    if (config.reader == ReaderKind::kRosbag) {
        out << YAML::Key << "rosbag" << YAML::Value << YAML::BeginMap;
        out << YAML::Key << "path" << YAML::Value << config.rosbag.path;
        out << YAML::Key << "radar_topic" << YAML::Value << config.rosbag.radar_topic;
        out << YAML::Key << "imu_topic" << YAML::Value << config.rosbag.imu_topic;
        out << YAML::Key << "ground_truth_topic" << YAML::Value << config.rosbag.ground_truth_topic;
        if (!config.rosbag.radar_trigger_topic.empty()) {
            out << YAML::Key << "radar_trigger_topic" << YAML::Value
                << config.rosbag.radar_trigger_topic;
            out << YAML::Key << "radar_trigger_offset_s" << YAML::Value
                << config.rosbag.radar_trigger_offset_s;
        }
        out << YAML::EndMap;
    } else if (config.reader == ReaderKind::kFolder) {
        out << YAML::Key << "folder" << YAML::Value << YAML::BeginMap;
        out << YAML::Key << "scans_dir" << YAML::Value << config.folder.scans_dir;
        out << YAML::Key << "extension" << YAML::Value << config.folder.extension;
        out << YAML::Key << "timestamps_file" << YAML::Value << config.folder.timestamps_file;
        out << YAML::Key << "columns" << YAML::Value << YAML::Flow << config.folder.columns;
        out << YAML::EndMap;
    }
    EmitFormatSection(out, config);
    EmitFieldMap(out, config);
    if (!config.ground_truth.path.empty()) {
        out << YAML::Key << "ground_truth" << YAML::Value << YAML::BeginMap;
        out << YAML::Key << "path" << YAML::Value << config.ground_truth.path;
        out << YAML::Key << "format" << YAML::Value << FormatName(config.ground_truth.format);
        if (!config.ground_truth.kitti_times_path.empty()) {
            out << YAML::Key << "kitti_times" << YAML::Value
                << config.ground_truth.kitti_times_path;
        }
        out << YAML::EndMap;
    }
    if (!config.imu.path.empty()) {
        out << YAML::Key << "imu" << YAML::Value << YAML::BeginMap;
        out << YAML::Key << "path" << YAML::Value << config.imu.path;
        out << YAML::Key << "format" << YAML::Value << ImuFormatName(config.imu.format);
        out << YAML::EndMap;
    }
    out << YAML::Key << "extrinsics" << YAML::Value << YAML::BeginMap;
    EmitTransform(out, "T_base_radar", config.extrinsics.T_base_radar);
    EmitTransform(out, "T_base_imu", config.extrinsics.T_base_imu);
    out << YAML::EndMap;
    out << YAML::Key << "vehicle" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "model" << YAML::Value << ToString(config.vehicle.model);
    out << YAML::Key << "half_wheelbase_m" << YAML::Value << config.vehicle.half_wheelbase_m;
    if (std::isfinite(config.vehicle.base_height_m))
        out << YAML::Key << "base_height_m" << YAML::Value << config.vehicle.base_height_m;
    const VehicleVelocityPrior &prior = config.vehicle.velocity_prior;
    if (prior.enabled) {  // written only when on: the simulator's descriptions stay as they were
        out << YAML::Key << "velocity_prior" << YAML::Value << YAML::BeginMap;
        out << YAML::Key << "enabled" << YAML::Value << true;
        out << YAML::Key << "sigma_lateral_mps" << YAML::Value << prior.sigma_lateral_mps;
        out << YAML::Key << "sigma_vertical_mps" << YAML::Value << prior.sigma_vertical_mps;
        out << YAML::EndMap;
    }
    const KinematicModelNoise &noise = config.vehicle.model_noise;
    out << YAML::Key << "model_noise" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "sigma_icr_x_m" << YAML::Value << noise.sigma_icr_x_m;
    out << YAML::Key << "rear_slip_rad_per_mps2" << YAML::Value << noise.rear_slip_rad_per_mps2;
    out << YAML::Key << "sigma_lateral_mps" << YAML::Value << noise.sigma_lateral_mps;
    out << YAML::Key << "sigma_vertical_mps" << YAML::Value << noise.sigma_vertical_mps;
    out << YAML::Key << "sigma_roll_rate_radps" << YAML::Value << noise.sigma_roll_rate_radps;
    EmitVector3(out, "angular_rate_prior_sigma_radps", noise.angular_rate_prior_sigma_radps);
    out << YAML::EndMap;
    out << YAML::EndMap;
    out << YAML::Key << "radar" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "range_sigma_m" << YAML::Value << config.radar.range_sigma_m;
    out << YAML::Key << "azimuth_sigma_deg" << YAML::Value << config.radar.azimuth_sigma_deg;
    out << YAML::Key << "elevation_sigma_deg" << YAML::Value << config.radar.elevation_sigma_deg;
    out << YAML::Key << "doppler_unambiguous_mps" << YAML::Value
        << config.radar.doppler_unambiguous_mps;
    out << YAML::Key << "geometry" << YAML::Value << ToString(config.radar.geometry);
    out << YAML::EndMap;
    out << YAML::EndMap;
    return std::string(out.c_str()) + "\n";
}

}  // namespace dorado::io
