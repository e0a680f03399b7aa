#include "nuscenes_tables.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>

#include "dorado/io/closest_name.hpp"
#include "dorado/io/dataset.hpp"

namespace dorado::io {

namespace fs = std::filesystem;

namespace {

// The devkit's order of the five radars: the front one first (the multi-radar map's reference).
const std::vector<std::string> kRadarOrder = {
    "RADAR_FRONT", "RADAR_FRONT_LEFT", "RADAR_FRONT_RIGHT", "RADAR_BACK_LEFT", "RADAR_BACK_RIGHT"};

// Applies `f` to each record of a table, streamed (each record is dropped once `f` has seen it),
// naming the table and the record on a parse error, a missing key or a wrong type.
template <typename F>
void ForEachRecord(const NuScenesSource &source, const char *table, F f) {
    const std::string path = NuScenesTablePath(source, table);
    std::ifstream in(path);
    if (!in) throw DatasetError(path + ": cannot open the nuScenes table");
    std::size_t index = 0;
    const auto where = [&] { return path + ": record " + std::to_string(index); };
    using Event = nlohmann::json::parse_event_t;
    const auto on_record = [&](int depth, Event event, nlohmann::json &parsed) {
        if (depth != 1 || (event != Event::object_end && event != Event::value)) return true;
        if (!parsed.is_object()) throw DatasetError(where() + ": not an object");
        try {
            f(parsed);
        } catch (const nlohmann::json::exception &e) {
            throw DatasetError(where() + ": " + e.what());
        } catch (const std::invalid_argument &e) {
            throw DatasetError(where() + ": " + e.what());
        }
        ++index;
        return false;  // not kept
    };
    nlohmann::json top;
    try {
        top = nlohmann::json::parse(in, on_record);
    } catch (const nlohmann::json::exception &e) {
        throw DatasetError(path + ": not valid JSON: " + e.what());
    }
    if (!top.is_array()) throw DatasetError(path + ": not a list of records");
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

std::string Listed(const std::vector<std::string> &names, std::size_t at_most) {
    std::string list;
    for (std::size_t i = 0; i < names.size() && i < at_most; ++i)
        list += (list.empty() ? "" : ", ") + names[i];
    if (names.size() > at_most) list += ", ... (" + std::to_string(names.size()) + " in all)";
    return list.empty() ? "none" : list;
}

// The scene's samples (by token).
std::set<std::string> SceneSamples(const NuScenesSource &source) {
    std::string scene_token;
    std::vector<std::string> names;
    ForEachRecord(source, "scene", [&](const nlohmann::json &r) {
        names.push_back(r.at("name").get<std::string>());
        if (names.back() == source.scene) scene_token = r.at("token").get<std::string>();
    });
    if (scene_token.empty()) {
        const std::string closest = ClosestName(source.scene, names, 3);
        throw DatasetError(NuScenesTablePath(source, "scene") + ": no scene named '" +
                           source.scene +
                           "' (nuscenes.scene, --scene); the scenes: " + Listed(names, 20) +
                           (closest.empty() ? "" : "; did you mean '" + closest + "'?"));
    }
    std::set<std::string> samples;
    ForEachRecord(source, "sample", [&](const nlohmann::json &r) {
        if (r.at("scene_token").get<std::string>() == scene_token)
            samples.insert(r.at("token").get<std::string>());
    });
    return samples;
}

// sensor.json: the radars' sensor tokens by channel (modality radar).
std::map<std::string, std::string> RadarSensors(const NuScenesSource &source) {
    std::map<std::string, std::string> sensors;  // channel -> token
    ForEachRecord(source, "sensor", [&](const nlohmann::json &r) {
        if (r.at("modality").get<std::string>() == "radar")
            sensors.emplace(r.at("channel").get<std::string>(), r.at("token").get<std::string>());
    });
    return sensors;
}

// The channels to read, in order: those asked for (each checked to be a radar of sensor.json), or
// every radar channel, the devkit's five first.
std::vector<std::string> ChannelsToRead(const NuScenesSource &source,
                                        const std::map<std::string, std::string> &sensors,
                                        const std::vector<std::string> &asked) {
    std::vector<std::string> names;
    for (const auto &[channel, token] : sensors) names.push_back(channel);
    for (const std::string &channel : asked) {
        if (sensors.count(channel)) continue;
        const std::string closest = ClosestName(channel, names, 3);
        throw DatasetError(NuScenesTablePath(source, "sensor") + ": no radar on channel '" +
                           channel +
                           "' (nuscenes.channel); the radar channels: " + Listed(names, 20) +
                           (closest.empty() ? "" : "; did you mean '" + closest + "'?"));
    }
    if (!asked.empty()) return asked;
    std::vector<std::string> order;
    for (const std::string &channel : kRadarOrder)
        if (sensors.count(channel)) order.push_back(channel);
    for (const std::string &channel : names)
        if (std::find(order.begin(), order.end(), channel) == order.end()) order.push_back(channel);
    return order;
}

}  // namespace

const Eigen::Isometry3d &NuScenesRadar::Mount(const NuScenesSource &source) const {
    if (!second_calibration.empty())
        throw DatasetError(NuScenesTablePath(source, "sample_data") + ": channel " + channel +
                           " has two calibrations in " + source.scene + " (" + calibration_token +
                           ", " + second_calibration +
                           "): read it alone (nuscenes.channel) with its mount as "
                           "extrinsics.T_base_radar");
    return T_ego_radar;
}

std::string NuScenesTablePath(const NuScenesSource &source, const char *table) {
    return (fs::path(source.dataroot) / source.version / (table + std::string(".json"))).string();
}

NuScenesScene IndexNuScenesScene(const NuScenesSource &source,
                                 const std::vector<std::string> &channels) {
    const std::map<std::string, std::string> sensors = RadarSensors(source);
    const std::vector<std::string> wanted = ChannelsToRead(source, sensors, channels);
    const std::set<std::string> samples = SceneSamples(source);
    std::map<std::string, std::size_t> radar_of_sensor;  // sensor token -> index in `wanted`
    for (std::size_t k = 0; k < wanted.size(); ++k) radar_of_sensor[sensors.at(wanted[k])] = k;
    // calibrated_sensor.json: every token (to name a sweep whose calibration has no record), the
    // wanted radars' poses.
    std::set<std::string> calibration_tokens;
    std::map<std::string, std::pair<std::size_t, Eigen::Isometry3d>> calibrations;
    std::vector<bool> calibrated(wanted.size(), false);
    ForEachRecord(source, "calibrated_sensor", [&](const nlohmann::json &r) {
        const std::string token = r.at("token").get<std::string>();
        calibration_tokens.insert(token);
        const auto radar = radar_of_sensor.find(r.at("sensor_token").get<std::string>());
        if (radar == radar_of_sensor.end()) return;
        calibrations.emplace(token, std::make_pair(radar->second, Pose(r)));
        calibrated[radar->second] = true;
    });
    for (std::size_t k = 0; k < wanted.size(); ++k) {
        if (!calibrated[k] && !channels.empty())
            throw DatasetError(NuScenesTablePath(source, "calibrated_sensor") +
                               ": no record of channel " + wanted[k] + " (its sensor_token " +
                               sensors.at(wanted[k]) + " in sensor.json): its mount is unknown");
    }
    std::vector<NuScenesRadar> radars(wanted.size());
    std::vector<NuScenesSweep> sweeps;
    std::size_t index = 0;
    ForEachRecord(source, "sample_data", [&](const nlohmann::json &r) {
        const std::size_t record = index++;
        if (!samples.count(r.at("sample_token").get<std::string>())) return;
        const std::string token = r.at("calibrated_sensor_token").get<std::string>();
        const std::string file = r.at("filename").get<std::string>();
        if (!calibration_tokens.count(token))
            throw DatasetError(NuScenesTablePath(source, "sample_data") + ": record " +
                               std::to_string(record) + " (" + file +
                               "): calibrated_sensor_token '" + token +
                               "' has no record in calibrated_sensor.json");
        const auto calibration = calibrations.find(token);
        if (calibration == calibrations.end()) return;  // another sensor
        const std::size_t k = calibration->second.first;
        NuScenesRadar &radar = radars[k];
        if (radar.calibration_token.empty()) {
            radar.channel = wanted[k];
            radar.calibration_token = token;
            radar.T_ego_radar = calibration->second.second;
        } else if (radar.calibration_token != token && radar.second_calibration.empty()) {
            radar.second_calibration = token;
        }
        sweeps.push_back(
            {r.at("timestamp").get<int64_t>(), (fs::path(source.dataroot) / file).string(), k});
    });
    // The radars without a sweep in the scene: an error when asked for, left out otherwise.
    std::vector<std::size_t> renumber(wanted.size());
    NuScenesScene scene;
    for (std::size_t k = 0; k < wanted.size(); ++k) {
        renumber[k] = scene.radars.size();
        if (!radars[k].calibration_token.empty()) {
            scene.radars.push_back(radars[k]);
        } else if (!channels.empty()) {
            throw DatasetError(NuScenesTablePath(source, "sample_data") + ": no " + wanted[k] +
                               " sweep in " + source.scene);
        }
    }
    if (scene.radars.empty())
        throw DatasetError(NuScenesTablePath(source, "sample_data") + ": no radar sweep in " +
                           source.scene);
    for (NuScenesSweep &s : sweeps) s.radar = renumber[s.radar];
    std::stable_sort(sweeps.begin(), sweeps.end(),
                     [](const NuScenesSweep &a, const NuScenesSweep &b) {
                         return a.timestamp_us != b.timestamp_us ? a.timestamp_us < b.timestamp_us
                                                                 : a.radar < b.radar;
                     });
    scene.sweeps = std::move(sweeps);
    return scene;
}

std::vector<std::pair<int64_t, Eigen::Isometry3d>> NuScenesEgoPoses(const NuScenesSource &source) {
    const std::set<std::string> samples = SceneSamples(source);
    std::set<std::string> tokens;
    ForEachRecord(source, "sample_data", [&](const nlohmann::json &r) {
        if (samples.count(r.at("sample_token").get<std::string>()))
            tokens.insert(r.at("ego_pose_token").get<std::string>());
    });
    std::map<int64_t, Eigen::Isometry3d> poses;  // one per time
    ForEachRecord(source, "ego_pose", [&](const nlohmann::json &r) {
        if (tokens.count(r.at("token").get<std::string>()))
            poses.emplace(r.at("timestamp").get<int64_t>(), Pose(r));
    });
    return {poses.begin(), poses.end()};
}

}  // namespace dorado::io
