// nuScenes (H. Caesar et al., CVPR 2020) radar sweeps in their own files, as
// nutonomy/nuscenes-devkit reads them:
// - the JSON tables under dataroot/version: scene (name, token), sample (scene_token), sensor
//   (channel), calibrated_sensor (sensor_token, translation, rotation w x y z = T_ego_sensor),
//   sample_data (sample_token, calibrated_sensor_token, ego_pose_token, timestamp [us], filename),
//   ego_pose (translation, rotation w x y z = T_global_ego);
// - each sweep a binary PCD v0.7 of the Continental ARS408's clusters: FIELDS x y z dyn_prop id rcs
//   vx vy vx_comp vy_comp is_quality_valid ambig_state x_rms y_rms invalid_state pdh0 vx_rms
//   vy_rms, SIZE 4 4 4 1 2 4 4 4 4 4 1 1 1 1 1 1 1 1, TYPE F F F I I F F F F F I I I I I I I I.
// A scan is one sweep of the configured channel in the configured scene, in time order, with every
// cluster (the devkit's optional state filters are not applied).
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "readers.hpp"

namespace dorado::io {

namespace fs = std::filesystem;

namespace {

constexpr int64_t kNanosPerMicro = 1000;

std::string TablePath(const DatasetConfig &config, const char *table) {
    return (fs::path(config.nuscenes.dataroot) / config.nuscenes.version /
            (table + std::string(".json")))
        .string();
}

nlohmann::json ReadTable(const DatasetConfig &config, const char *table) {
    const std::string path = TablePath(config, table);
    std::ifstream in(path);
    if (!in) throw DatasetError(path + ": cannot open the nuScenes table");
    try {
        nlohmann::json json = nlohmann::json::parse(in);
        if (!json.is_array()) throw DatasetError(path + ": not a list of records");
        return json;
    } catch (const nlohmann::json::exception &e) {
        throw DatasetError(path + ": not valid JSON: " + e.what());
    }
}

// Rigid transform from nuScenes' translation [x, y, z] and rotation [w, x, y, z].
Eigen::Isometry3d Pose(const nlohmann::json &record) {
    const auto t = record.at("translation").get<std::vector<double>>();
    const auto q = record.at("rotation").get<std::vector<double>>();
    if (t.size() != 3 || q.size() != 4)
        throw std::invalid_argument("translation needs 3 values and rotation 4 (w x y z)");
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() << t[0], t[1], t[2];
    T.linear() = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
    return T;
}

struct Sweep {
    int64_t timestamp_us = 0;
    std::string file;  ///< absolute
    std::string calibrated_sensor_token;
};

// Applies `f` to each record of a table, naming the table and the record on a missing key.
template <typename F>
void ForEachRecord(const DatasetConfig &config, const char *table, F f) {
    const nlohmann::json records = ReadTable(config, table);
    for (std::size_t i = 0; i < records.size(); ++i) {
        try {
            f(records[i]);
        } catch (const nlohmann::json::exception &e) {
            throw DatasetError(TablePath(config, table) + ": record " + std::to_string(i) + ": " +
                               e.what());
        } catch (const std::invalid_argument &e) {
            throw DatasetError(TablePath(config, table) + ": record " + std::to_string(i) + ": " +
                               e.what());
        }
    }
}

// The scene's samples (by token).
std::set<std::string> SceneSamples(const DatasetConfig &config) {
    std::string scene_token;
    ForEachRecord(config, "scene", [&](const nlohmann::json &r) {
        if (r.at("name").get<std::string>() == config.nuscenes.scene)
            scene_token = r.at("token").get<std::string>();
    });
    if (scene_token.empty())
        throw DatasetError(TablePath(config, "scene") + ": no scene named '" +
                           config.nuscenes.scene + "' (nuscenes.scene)");
    std::set<std::string> samples;
    ForEachRecord(config, "sample", [&](const nlohmann::json &r) {
        if (r.at("scene_token").get<std::string>() == scene_token)
            samples.insert(r.at("token").get<std::string>());
    });
    return samples;
}

// The calibrations of the configured channel (by token), with T_ego_sensor.
std::map<std::string, Eigen::Isometry3d> ChannelCalibrations(const DatasetConfig &config) {
    std::set<std::string> sensors;
    ForEachRecord(config, "sensor", [&](const nlohmann::json &r) {
        if (r.at("channel").get<std::string>() == config.nuscenes.channel)
            sensors.insert(r.at("token").get<std::string>());
    });
    if (sensors.empty())
        throw DatasetError(TablePath(config, "sensor") + ": no sensor on channel '" +
                           config.nuscenes.channel + "' (nuscenes.channel)");
    std::map<std::string, Eigen::Isometry3d> calibrations;
    ForEachRecord(config, "calibrated_sensor", [&](const nlohmann::json &r) {
        if (sensors.count(r.at("sensor_token").get<std::string>()))
            calibrations.emplace(r.at("token").get<std::string>(), Pose(r));
    });
    return calibrations;
}

// The channel's sweeps in the scene, in time order.
std::vector<Sweep> ChannelSweeps(const DatasetConfig &config) {
    const auto samples = SceneSamples(config);
    const auto calibrations = ChannelCalibrations(config);
    std::vector<Sweep> sweeps;
    ForEachRecord(config, "sample_data", [&](const nlohmann::json &r) {
        if (!samples.count(r.at("sample_token").get<std::string>())) return;
        Sweep s;
        s.calibrated_sensor_token = r.at("calibrated_sensor_token").get<std::string>();
        if (!calibrations.count(s.calibrated_sensor_token)) return;
        s.timestamp_us = r.at("timestamp").get<int64_t>();
        s.file =
            (fs::path(config.nuscenes.dataroot) / r.at("filename").get<std::string>()).string();
        sweeps.push_back(s);
    });
    if (sweeps.empty())
        throw DatasetError(TablePath(config, "sample_data") + ": no " + config.nuscenes.channel +
                           " sweep in " + config.nuscenes.scene);
    std::sort(sweeps.begin(), sweeps.end(),
              [](const Sweep &a, const Sweep &b) { return a.timestamp_us < b.timestamp_us; });
    return sweeps;
}

// One PCD field as the header describes it.
struct PcdField {
    std::string name;
    char type = 'F';
    std::size_t size = 4, count = 1, offset = 0;
};

// Decodes a binary PCD v0.7 radar sweep into a scan; throws DecodeError naming the field.
RadarScan DecodeSweep(const std::string &file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw DecodeError("cannot open");
    std::vector<PcdField> fields;
    std::size_t points = 0;
    std::string line, data;
    std::map<std::string, std::vector<std::string>> header;
    while (data.empty() && std::getline(in, line)) {
        std::istringstream tokens(line);
        std::string key;
        tokens >> key;
        if (key.empty() || key[0] == '#') continue;
        for (std::string v; tokens >> v;) header[key].push_back(v);
        if (key == "DATA") data = header[key].empty() ? "?" : header[key][0];
    }
    if (data != "binary")
        throw DecodeError("not a binary PCD (DATA " + (data.empty() ? "missing" : data) + ")");
    const auto &names = header["FIELDS"], &sizes = header["SIZE"], &types = header["TYPE"];
    auto counts = header["COUNT"];
    if (counts.empty()) counts.assign(names.size(), "1");
    if (names.empty() || sizes.size() != names.size() || types.size() != names.size() ||
        counts.size() != names.size())
        throw DecodeError("the header's FIELDS, SIZE, TYPE and COUNT differ in length");
    std::size_t step = 0;
    for (std::size_t i = 0; i < names.size(); ++i) {
        PcdField f{names[i], types[i].empty() ? '?' : types[i][0], 0, 0, step};
        try {
            f.size = std::stoul(sizes[i]);
            f.count = std::stoul(counts[i]);
            points = header["POINTS"].empty() ? 0 : std::stoul(header["POINTS"][0]);
        } catch (const std::logic_error &) {
            throw DecodeError("field '" + f.name + "': SIZE, COUNT or POINTS is not a number");
        }
        if (f.size == 0 || f.size > 8 || f.count == 0 || f.count > 65536)
            throw DecodeError("field '" + f.name + "': SIZE " + std::to_string(f.size) +
                              " or COUNT " + std::to_string(f.count) + " out of range");
        step += f.size * f.count;
        fields.push_back(f);
    }
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)),
                                  std::istreambuf_iterator<char>());
    if (points > bytes.size() / step)  // step > 0: every field has SIZE and COUNT >= 1
        throw DecodeError("truncated: " + std::to_string(points) + " points of " +
                          std::to_string(step) + " bytes need " + std::to_string(points * step) +
                          " bytes after the header, the file has " + std::to_string(bytes.size()));
    // The fields dorado uses, each a float32 in nuScenes' schema.
    const auto offset = [&](const char *name) {
        const auto it = std::find_if(fields.begin(), fields.end(),
                                     [&](const PcdField &f) { return f.name == name; });
        if (it == fields.end()) throw DecodeError(std::string("missing field '") + name + "'");
        if (it->type != 'F' || it->size != 4 || it->count != 1)
            throw DecodeError(std::string("field '") + name + "' is " + it->type +
                              std::to_string(it->size) + " x" + std::to_string(it->count) +
                              ", expected one float32 (F 4) as in nuScenes' radar sweeps");
        return it->offset;
    };
    const std::size_t ox = offset("x"), oy = offset("y"), oz = offset("z"), orcs = offset("rcs"),
                      ovx = offset("vx"), ovy = offset("vy");
    const auto value = [&](std::size_t point, std::size_t field_offset) {
        float v;
        std::memcpy(&v, bytes.data() + point * step + field_offset, sizeof(v));  // little-endian
        return static_cast<double>(v);
    };
    RadarScan scan;
    scan.Resize(static_cast<Eigen::Index>(points));
    scan.has_power = true;
    for (std::size_t k = 0; k < points; ++k) {
        const auto i = static_cast<Eigen::Index>(k);
        const double x = value(k, ox), y = value(k, oy);
        scan.xyz_radar.col(i) << x, y, value(k, oz);
        scan.power_db[i] = value(k, orcs);
        // The radial velocity the radar measured: the uncompensated velocity along the line of
        // sight (NaN at the origin: removed as a non-finite point).
        scan.doppler_mps[i] = (x * value(k, ovx) + y * value(k, ovy)) / std::hypot(x, y);
    }
    scan.DeriveSphericalFromXyz();
    return scan;
}

class NuScenesReader final : public DatasetReader {
  public:
    explicit NuScenesReader(const DatasetConfig &config)
        : source_(config.nuscenes.dataroot + " (" + config.nuscenes.scene + ", " +
                  config.nuscenes.channel + ")"),
          channel_(config.nuscenes.channel),
          sweeps_(ChannelSweeps(config)) {}

    bool Next(DatasetEvent &event) override {
        if (next_ >= sweeps_.size()) return false;
        event = DatasetEvent{};
        event.scan_index = next_;
        const Sweep &sweep = sweeps_[next_++];
        event.stamp_ns = sweep.timestamp_us * kNanosPerMicro;
        try {
            event.scan = DecodeSweep(sweep.file);
        } catch (const DecodeError &e) {
            event.kind = DatasetEvent::Kind::kBadScan;
            event.problem =
                sweep.file + " (scan " + std::to_string(event.scan_index) + "): " + e.what();
            return true;
        }
        event.kind = DatasetEvent::Kind::kRadarScan;
        event.scan.stamp_ns = event.stamp_ns;
        event.scan.frame_id = channel_;
        event.removed_nonfinite_points = RemoveNonFinitePoints(event.scan);
        return true;
    }

    [[nodiscard]] std::string source() const override { return source_; }

  private:
    std::string source_, channel_;
    std::vector<Sweep> sweeps_;
    std::size_t next_ = 0;
};

}  // namespace

std::unique_ptr<DatasetReader> OpenNuScenesReader(const DatasetConfig &config) {
    return std::make_unique<NuScenesReader>(config);
}

Eigen::Isometry3d NuScenesMount(const DatasetConfig &config) {
    const auto calibrations = ChannelCalibrations(config);
    const auto sweeps = ChannelSweeps(config);
    const std::string &token = sweeps.front().calibrated_sensor_token;
    for (const Sweep &s : sweeps) {
        if (s.calibrated_sensor_token != token)
            throw DatasetError(TablePath(config, "sample_data") + ": " + config.nuscenes.channel +
                               " has more than one calibration in " + config.nuscenes.scene +
                               ": give the mount as extrinsics.T_base_radar");
    }
    return calibrations.at(token);  // T_ego_radar: nuScenes' ego frame is the rear axle's centre
}

Trajectory LoadNuScenesEgoPoses(const DatasetConfig &config) {
    // Every sample_data of the scene (all channels) has the ego pose at its time.
    const auto samples = SceneSamples(config);
    std::set<std::string> tokens;
    ForEachRecord(config, "sample_data", [&](const nlohmann::json &r) {
        if (samples.count(r.at("sample_token").get<std::string>()))
            tokens.insert(r.at("ego_pose_token").get<std::string>());
    });
    std::map<int64_t, Eigen::Isometry3d> poses;  // one per time
    ForEachRecord(config, "ego_pose", [&](const nlohmann::json &r) {
        if (tokens.count(r.at("token").get<std::string>()))
            poses.emplace(r.at("timestamp").get<int64_t>() * kNanosPerMicro, Pose(r));
    });
    std::vector<StampedPose> stamped;
    for (const auto &[t, T] : poses) stamped.push_back({t, T});
    return Trajectory(std::move(stamped));
}

}  // namespace dorado::io
