// RadarScenes (O. Schumann et al., FUSION 2021) in its own files, as its devkit
// (oleschum/radar_scenes) reads them:
// - radar_data.h5, table `radar_data`: one row per detection (timestamp [us], sensor_id, range_sc,
//   azimuth_sc, rcs, vr, vr_compensated, x_cc, y_cc, x_seq, y_seq, uuid, track_id, label_id);
//   table `odometry`: the car's pose per odometry time (timestamp, x_seq, y_seq, yaw_seq, vx,
//   yaw_rate);
// - scenes.json: `scenes`, keyed by timestamp, each with sensor_id and radar_indices [first, end)
//   into radar_data (one scene = one measurement of one radar);
// - sensors.json: `radar_<id>` with the mount x, y [m], yaw [rad] in the car frame (rear axle).
// A scan is one scene of one of the sensors read (scenes of several sensors merged in time order);
// its rows are checked to be that sensor's at that timestamp.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "h5_table.hpp"
#include "readers.hpp"

namespace dorado::io {

namespace fs = std::filesystem;

namespace {

constexpr int64_t kNanosPerMicro = 1000;

nlohmann::json ReadJson(const std::string &path) {
    std::ifstream in(path);
    if (!in) throw DatasetError(path + ": cannot open");
    try {
        return nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception &e) {
        throw DatasetError(path + ": not valid JSON: " + e.what());
    }
}

struct Scene {
    int64_t timestamp_us = 0;
    std::size_t first_row = 0, end_row = 0;
    std::size_t radar = 0;  ///< index into the sensor ids read
};

std::string SensorList(std::vector<int> ids) {
    std::sort(ids.begin(), ids.end());
    std::string list;
    for (int id : ids) list += (list.empty() ? "" : ", ") + std::to_string(id);
    return list.empty() ? "none" : list;
}

// What scenes.json holds of the sensors asked for.
struct SequenceScenes {
    std::vector<Scene> scenes;  ///< theirs, in time order (equal times: by index in the list)
    std::vector<int> sensors;   ///< every sensor with a scene in the sequence
};

SequenceScenes ReadScenes(const std::string &path, const std::vector<int> &sensor_ids) {
    const nlohmann::json json = ReadJson(path);
    if (!json.contains("scenes") || !json["scenes"].is_object())
        throw DatasetError(path + ": no 'scenes' object");
    SequenceScenes read;
    std::vector<Scene> &scenes = read.scenes;
    std::vector<int> &sensors = read.sensors;
    for (const auto &[key, scene] : json["scenes"].items()) {
        try {
            const int id = scene.at("sensor_id").get<int>();
            if (std::find(sensors.begin(), sensors.end(), id) == sensors.end())
                sensors.push_back(id);
            const auto radar = std::find(sensor_ids.begin(), sensor_ids.end(), id);
            if (radar == sensor_ids.end()) continue;
            const auto &indices = scene.at("radar_indices");
            if (!indices.is_array() || indices.size() != 2)
                throw DatasetError(path + ": scene " + key + ": radar_indices is not [first, end]");
            Scene s;
            s.timestamp_us = std::stoll(key);
            s.first_row = indices[0].get<std::size_t>();
            s.end_row = indices[1].get<std::size_t>();
            s.radar = static_cast<std::size_t>(radar - sensor_ids.begin());
            scenes.push_back(s);
        } catch (const nlohmann::json::exception &e) {
            throw DatasetError(path + ": scene " + key + ": " + e.what());
        } catch (const std::logic_error &) {
            throw DatasetError(path + ": scene key '" + key + "' is not a timestamp");
        }
    }
    for (int id : sensor_ids) {
        if (std::find(sensors.begin(), sensors.end(), id) == sensors.end())
            throw DatasetError(path + ": no scene of sensor_id " + std::to_string(id) +
                               " (the sequence has sensors " + SensorList(sensors) + ")");
    }
    std::sort(scenes.begin(), scenes.end(), [](const Scene &a, const Scene &b) {
        return a.timestamp_us != b.timestamp_us ? a.timestamp_us < b.timestamp_us
                                                : a.radar < b.radar;
    });
    return read;
}

SequenceScenes ReadScenes(const DatasetConfig &config, const std::vector<int> &sensor_ids) {
    return ReadScenes((RadarScenesSequenceDir(config) / "scenes.json").string(), sensor_ids);
}

// sensors.json: the data set keeps it next to the sequence folders; a copy inside one also works.
fs::path SensorsJson(const DatasetConfig &config) {
    const fs::path dir = RadarScenesSequenceDir(config);
    fs::path path = dir / "sensors.json";
    if (!fs::exists(path)) path = dir.parent_path() / "sensors.json";
    if (!fs::exists(path))
        throw DatasetError((dir / "sensors.json").string() + ": missing (and none in " +
                           dir.parent_path().string() +
                           "): give the mount as extrinsics.T_base_radar");
    return path;
}

// T_base_radar of radar_<id> in sensors.json: x, y [m], yaw [rad] in the car frame.
Eigen::Isometry3d SensorMount(const fs::path &path, const nlohmann::json &json, int sensor_id) {
    const std::string name = "radar_" + std::to_string(sensor_id);
    Eigen::Isometry3d T_base_radar = Eigen::Isometry3d::Identity();
    try {
        const auto &mount = json.at(name);
        T_base_radar.translation() << mount.at("x").get<double>(), mount.at("y").get<double>(),
            0.0;  // no height in the data set: the radar's plane is the car's
        T_base_radar.linear() =
            Eigen::AngleAxisd(mount.at("yaw").get<double>(), Eigen::Vector3d::UnitZ())
                .toRotationMatrix();
    } catch (const nlohmann::json::exception &e) {
        throw DatasetError(path.string() + ": " + name + ": " + e.what());
    }
    return T_base_radar;
}

std::string H5Path(const DatasetConfig &config) {
    return (RadarScenesSequenceDir(config) / "radar_data.h5").string();
}

class RadarScenesReader final : public DatasetReader {
  public:
    RadarScenesReader(const DatasetConfig &config, const std::vector<int> &sensor_ids)
        : source_(H5Path(config) + " (sensor_id " + SensorList(sensor_ids) + ")"),
          sensor_ids_(sensor_ids),
          scenes_(ReadScenes(config, sensor_ids).scenes),
          scans_of_radar_(sensor_ids.size(), 0),
          file_(OpenH5File(H5Path(config))),
          table_(file_, H5Path(config), "radar_data",
                 {{"timestamp", ColumnKind::kInteger},
                  {"sensor_id", ColumnKind::kInteger},
                  {"range_sc", ColumnKind::kFloat},
                  {"azimuth_sc", ColumnKind::kFloat},
                  {"rcs", ColumnKind::kFloat},
                  {"vr", ColumnKind::kFloat}}) {}

    bool Next(DatasetEvent &event) override {
        if (next_ >= scenes_.size()) return false;
        event = DatasetEvent{};
        const Scene &scene = scenes_[next_++];
        event.radar = scene.radar;
        event.scan_index = scans_of_radar_[scene.radar]++;
        event.stamp_ns = scene.timestamp_us * kNanosPerMicro;
        std::string problem;
        std::vector<H5Value> rows;
        if (scene.first_row > scene.end_row || scene.end_row > table_.rows()) {
            problem = "radar_indices [" + std::to_string(scene.first_row) + ", " +
                      std::to_string(scene.end_row) + ") outside the table's " +
                      std::to_string(table_.rows()) + " rows";
        } else {
            rows = table_.Rows(scene.first_row, scene.end_row - scene.first_row);
            problem = CheckRows(scene, sensor_ids_[scene.radar], rows);
        }
        if (!problem.empty()) {
            event.kind = DatasetEvent::Kind::kBadScan;
            event.problem = table_.Where("timestamp") + " (scan " +
                            std::to_string(event.scan_index) + ", scene " +
                            std::to_string(scene.timestamp_us) + "): " + problem;
            return true;
        }
        event.kind = DatasetEvent::Kind::kRadarScan;
        event.scan = ToScan(rows);
        event.scan.stamp_ns = event.stamp_ns;
        event.scan.frame_id = "radar_" + std::to_string(sensor_ids_[scene.radar]);
        event.removed_nonfinite_points = RemoveNonFinitePoints(event.scan);
        return true;
    }

    [[nodiscard]] std::string source() const override { return source_; }

  private:
    // The columns given to table_, in that order (one value each per row of Rows()).
    enum Column { kTimestamp, kSensor, kRange, kAzimuth, kRcs, kVr, kColumns };

    // Empty when rows [first, end) are all this sensor's at the scene's timestamp.
    [[nodiscard]] static std::string CheckRows(const Scene &scene, int sensor_id,
                                               const std::vector<H5Value> &rows) {
        for (std::size_t r = 0; r < rows.size() / kColumns; ++r) {
            const int64_t stamp = rows[r * kColumns + kTimestamp].i;
            const int64_t sensor = rows[r * kColumns + kSensor].i;
            if (stamp != scene.timestamp_us || sensor != sensor_id)
                return "row " + std::to_string(scene.first_row + r) + " is sensor " +
                       std::to_string(sensor) + " at " + std::to_string(stamp) +
                       ", not the scene's sensor " + std::to_string(sensor_id);
        }
        return "";
    }

    [[nodiscard]] static RadarScan ToScan(const std::vector<H5Value> &rows) {
        const std::size_t n = rows.size() / kColumns;
        RadarScan scan;
        scan.Resize(static_cast<Eigen::Index>(n));
        scan.has_power = true;
        for (std::size_t k = 0; k < n; ++k) {
            const auto i = static_cast<Eigen::Index>(k);
            const H5Value *row = &rows[k * kColumns];
            const double range = row[kRange].f, azimuth = row[kAzimuth].f;
            // Sensor coordinates: x forward, azimuth from x towards y, no elevation (a 2D radar).
            scan.xyz_radar.col(i) << range * std::cos(azimuth), range * std::sin(azimuth), 0.0;
            scan.range_m[i] = range;
            scan.azimuth_rad[i] = azimuth;
            scan.elevation_rad[i] = 0.0;
            scan.power_db[i] = row[kRcs].f;
            scan.doppler_mps[i] = row[kVr].f;  // raw radial velocity, positive = receding
        }
        return scan;
    }

    std::string source_;
    std::vector<int> sensor_ids_;
    std::vector<Scene> scenes_;
    std::vector<std::size_t> scans_of_radar_;
    H5Id file_;
    H5Table table_;
    std::size_t next_ = 0;
};

}  // namespace

std::unique_ptr<DatasetReader> OpenRadarScenesReader(const DatasetConfig &config,
                                                     const std::vector<int> &sensor_ids) {
    return std::make_unique<RadarScenesReader>(config, sensor_ids);
}

Trajectory LoadRadarScenesOdometry(const DatasetConfig &config) {
    const std::string path = H5Path(config);
    const H5Id file = OpenH5File(path);
    const H5Table odometry(file, path, "odometry",
                           {{"timestamp", ColumnKind::kInteger},
                            {"x_seq", ColumnKind::kFloat},
                            {"y_seq", ColumnKind::kFloat},
                            {"yaw_seq", ColumnKind::kFloat}});
    const std::size_t n = odometry.rows();
    const auto t = odometry.Integers("timestamp", 0, n);
    const auto x = odometry.Floats("x_seq", 0, n), y = odometry.Floats("y_seq", 0, n),
               yaw = odometry.Floats("yaw_seq", 0, n);
    std::vector<StampedPose> poses(n);
    for (std::size_t i = 0; i < n; ++i) {
        poses[i].stamp_ns = t[i] * kNanosPerMicro;
        poses[i].T_world_body.translation() << x[i], y[i], 0.0;  // the sequence frame, 2D
        poses[i].T_world_body.linear() =
            Eigen::AngleAxisd(yaw[i], Eigen::Vector3d::UnitZ()).toRotationMatrix();
    }
    try {
        return Trajectory(std::move(poses));
    } catch (const std::invalid_argument &e) {
        throw DatasetError(odometry.Where("timestamp") + ": " + e.what());
    }
}

Eigen::Isometry3d RadarScenesMount(const DatasetConfig &config) {
    const fs::path path = SensorsJson(config);
    return SensorMount(path, ReadJson(path.string()), OneRadarScenesSensor(config));
}

std::vector<RadarStream> RadarScenesRadars(const DatasetConfig &config) {
    const fs::path path = SensorsJson(config);
    const nlohmann::json json = ReadJson(path.string());
    std::vector<int> present = ReadScenes(config, {}).sensors;
    std::sort(present.begin(), present.end());
    std::vector<RadarStream> radars;
    for (const int id : present) {
        RadarStream radar;
        radar.name = "radar_" + std::to_string(id);
        radar.radarscenes_sensor_id = id;
        radar.T_base_radar = SensorMount(path, json, id);
        radars.push_back(radar);
    }
    if (radars.empty())
        throw DatasetError((RadarScenesSequenceDir(config) / "scenes.json").string() +
                           ": no scene");
    return radars;
}

}  // namespace dorado::io
