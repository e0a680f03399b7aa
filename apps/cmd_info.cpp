// `dorado info DATASET`: what a dataset holds and what is wrong with it.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <map>
#include <utility>

#include "commands.hpp"
#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/core/time.hpp"
#include "dorado/io/dataset.hpp"
#include "dorado/io/folder_layout.hpp"
#include "progress.hpp"
#include "scan_loop.hpp"

namespace dorado::apps {

namespace {

/// Problems of one kind: counted, the first few kept as examples.
class ProblemLog {
  public:
    void Add(const std::string &kind, const std::string &example) {
        auto &entry = problems_[kind];
        if (entry.count++ < kExamples) entry.examples.push_back(example);
    }
    [[nodiscard]] bool Has(const std::string &kind) const { return problems_.count(kind) > 0; }
    void Print() const {
        if (problems_.empty()) {
            std::printf("problems: none found\n");
            return;
        }
        std::printf("problems:\n");
        for (const auto &[kind, entry] : problems_) {
            std::printf("  %s: %zu\n", kind.c_str(), entry.count);
            for (const auto &e : entry.examples) std::printf("    - %s\n", e.c_str());
            if (entry.count > entry.examples.size())
                std::printf("    - ... and %zu more\n", entry.count - entry.examples.size());
        }
    }

  private:
    static constexpr std::size_t kExamples = 5;
    struct Entry {
        std::size_t count = 0;
        std::vector<std::string> examples;
    };
    std::map<std::string, Entry> problems_;
};

double Median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

// A topic's message rate over its time span [Hz] (0 with fewer than 2 messages).
double Rate(const io::TopicSummary &t) {
    const double span_s = NanosToSeconds(t.last_ns - t.first_ns);
    return span_s > 0 && t.messages > 1 ? static_cast<double>(t.messages - 1) / span_s : 0.0;
}

void PrintTopics(const std::vector<io::TopicSummary> &topics, const io::DatasetConfig &config) {
    std::printf("topics:\n");
    for (const auto &t : topics) {
        const double span_s = NanosToSeconds(t.last_ns - t.first_ns);
        const double rate = Rate(t);
        std::string role;
        if (t.topic == config.rosbag.radar_topic) role = "  <- radar";
        if (t.topic == config.rosbag.imu_topic || t.topic == config.imu.path) role = "  <- imu";
        if (t.topic == config.rosbag.ground_truth_topic) role = "  <- ground truth";
        std::printf("  %-32s %-28s %7zu msgs %8.2f s %7.2f Hz%s\n", t.topic.c_str(), t.type.c_str(),
                    t.messages, span_s, rate, role.c_str());
        if (!t.fields.empty()) std::printf("      fields: %s\n", t.fields.c_str());
    }
}

// One radar of the `radars:` list read through: its layout, every scan file, its times. Each
// problem is named with the radar's name.
void CheckRadarScans(const io::DatasetConfig &one, const std::string &name, ProblemLog &problems) {
    if (const auto layout = io::CheckFolderLayout(one)) {
        problems.Add("radars whose scan files do not fit the description",
                     name + ": " + layout->message + " (fix: " + layout->fix + ")");
        return;
    }
    auto reader = io::OpenDataset(one);
    io::DatasetEvent event;
    int64_t last_ns = INT64_MIN;
    while (reader->Next(event)) {
        const std::string where = name + " scan " + std::to_string(event.scan_index);
        if (event.kind == io::DatasetEvent::Kind::kBadScan) {
            problems.Add("unreadable scans", name + ": " + event.problem);
        } else if (event.kind == io::DatasetEvent::Kind::kRadarScan) {
            if (event.stamp_ns <= last_ns) problems.Add("radar time not increasing", where);
            last_ns = event.stamp_ns;
            if (event.removed_nonfinite_points > 0)
                problems.Add(
                    "scans with NaN/Inf points (removed)",
                    where + ": " + std::to_string(event.removed_nonfinite_points) + " points");
            if (event.scan.empty()) problems.Add("empty scans", where);
        }
    }
}

// The `radars:` list (several radars on one vehicle): each one's mount, and its scans read
// through as the first radar's are (dorado map and dorado twist read them all).
void PrintRadars(const io::DatasetConfig &config, ProblemLog &problems) {
    if (config.radars.empty()) return;
    std::printf("radars: %zu (the radars: list; dorado map and dorado twist read them all)\n",
                config.radars.size());
    for (std::size_t k = 0; k < config.radars.size(); ++k) {
        const io::RadarStream &radar = config.radars[k];
        const Eigen::Vector3d t = radar.T_base_radar.translation();
        const double yaw_deg = RadToDeg(RollPitchYaw(radar.T_base_radar.linear()).z());
        std::printf("  %-17s mount x %6.3f y %6.3f z %5.2f m, yaw %8.3f deg", radar.name.c_str(),
                    t.x(), t.y(), t.z(), yaw_deg);
        try {
            io::DatasetConfig one = io::ForRadar(config, k);
            one.imu.path.clear();  // its scans only: the IMU file is listed above
            const io::TopicSummary scans = io::ListTopics(one).front();
            std::printf(", %zu scans, %.2f s, %.2f Hz\n", scans.messages,
                        NanosToSeconds(scans.last_ns - scans.first_ns), Rate(scans));
            CheckRadarScans(one, radar.name, problems);
        } catch (const std::exception &e) {
            std::printf(", unreadable\n");
            problems.Add("radars that cannot be read", radar.name + ": " + e.what());
        }
    }
}

std::string DescribeSource(const io::DatasetConfig &config) {
    switch (config.reader) {
        case io::ReaderKind::kRosbag:
            return "rosbag " + config.rosbag.path;
        case io::ReaderKind::kFolder:
            return "folder " + config.folder.scans_dir;
        case io::ReaderKind::kRadarScenes:
            return "RadarScenes " + config.radarscenes.sequence_dir + ", " +
                   (config.radarscenes.sensor_id == 0
                        ? "every radar"
                        : "sensor_id " + std::to_string(config.radarscenes.sensor_id));
        case io::ReaderKind::kNuScenes:
            return "nuScenes " + config.nuscenes.dataroot + " " + config.nuscenes.version + ", " +
                   config.nuscenes.scene + ", " +
                   (config.nuscenes.channel.empty() ? "every radar" : config.nuscenes.channel);
    }
    return "";
}

int RunInfo(const std::string &dataset_arg, const std::string &data_dir,
            const io::DatasetChoice &choice) {
    const io::DatasetConfig config = io::ResolveDataset(dataset_arg, data_dir, choice);
    const bool is_bag = config.reader == io::ReaderKind::kRosbag;
    std::printf("dataset: %s (%s)\n", config.name.c_str(), DescribeSource(config).c_str());
    // A layout the folder's files do not fit: every scan would be refused or read wrongly.
    if (const auto layout = io::CheckFolderLayout(config)) {
        std::printf(
            "problems:\n  scan files that do not fit the description: the folder is "
            "refused\n    - %s\n    fix: %s\n",
            layout->message.c_str(), layout->fix.c_str());
        return 1;
    }
    const auto topics = io::ListTopics(config);
    PrintTopics(topics, config);
    std::size_t expected_scans = 0;
    for (const auto &t : topics) {
        if (is_bag ? t.topic == config.rosbag.radar_topic : t.topic != config.imu.path)
            expected_scans = t.messages;
    }

    auto reader = io::OpenDataset(config);
    ProblemLog problems;
    // A topic the description names that is in the bag (a connection) but has no message.
    const std::pair<std::string, const char *> roles[] = {
        {config.rosbag.radar_topic, "rosbag.radar_topic"},
        {config.rosbag.imu_topic, "rosbag.imu_topic"},
        {config.rosbag.ground_truth_topic, "rosbag.ground_truth_topic"}};
    for (const auto &t : topics)
        for (const auto &[topic, key] : roles)
            if (is_bag && t.messages == 0 && t.topic == topic)
                problems.Add("configured topics without messages", t.topic + " (" + key + ")");
    Progress progress("reading scans", expected_scans);
    std::vector<double> points, intervals_ms;
    std::vector<std::size_t> interval_ends;  // the scan index that ends each interval
    std::size_t scans = 0, bad = 0, imu = 0, gt = 0;
    // As the front end pairs them: the IMU samples that arrived before a scan, stamped in its
    // interval (previous scan, scan]. None there = no gyro rotation for that scan.
    ImuWindow imu_window;
    const bool has_imu_topic = HasImu(config);
    int64_t first_ns = 0, last_ns = 0, last_imu_ns = INT64_MIN;
    double min_doppler = 0.0, max_doppler = 0.0;
    std::size_t scans_with_points = 0, planar_scans = 0;  // every z exactly 0: a 2D radar's
    io::DatasetEvent event;
    while (reader->Next(event)) {
        switch (event.kind) {
            case io::DatasetEvent::Kind::kBadScan:
                ++bad;
                problems.Add("unreadable scans", event.problem);
                break;
            case io::DatasetEvent::Kind::kImu:
                if (event.stamp_ns <= last_imu_ns)
                    problems.Add("IMU time not increasing",
                                 "at " + std::to_string(NanosToSeconds(event.stamp_ns)) + " s");
                last_imu_ns = event.stamp_ns;
                if (!event.imu.omega_imu_radps.allFinite() ||
                    !event.imu.accel_imu_mps2.allFinite()) {
                    problems.Add("IMU samples with NaN/Inf",
                                 "at " + std::to_string(NanosToSeconds(event.stamp_ns)) + " s");
                }
                ++imu;
                imu_window.Add(event.imu);
                break;
            case io::DatasetEvent::Kind::kGroundTruth:
                ++gt;
                break;
            case io::DatasetEvent::Kind::kRadarScan: {
                const std::string where = "scan " + std::to_string(event.scan_index);
                if (scans == 0) {
                    first_ns = event.stamp_ns;
                } else {
                    const double dt_ms = NanosToSeconds(event.stamp_ns - last_ns) * 1e3;
                    if (dt_ms <= 0.0) {
                        char text[96];
                        std::snprintf(text, sizeof(text), "%s: %.1f ms after the previous scan",
                                      where.c_str(), dt_ms);
                        problems.Add("radar time not increasing", text);
                    } else {
                        intervals_ms.push_back(dt_ms);
                        interval_ends.push_back(event.scan_index);
                    }
                    if (has_imu_topic && imu_window.Between(last_ns, event.stamp_ns).empty()) {
                        char text[160];
                        std::snprintf(
                            text, sizeof(text),
                            "%s: stamp %.3f s, newest IMU stamp %.3f s (different clocks?)",
                            where.c_str(), NanosToSeconds(event.stamp_ns),
                            NanosToSeconds(imu_window.newest_stamp_ns()));
                        problems.Add("scan intervals without IMU samples (no gyro rotation there)",
                                     text);
                    }
                }
                imu_window.DropUpTo(event.stamp_ns - 1);
                last_ns = std::max(last_ns, event.stamp_ns);
                if (event.removed_nonfinite_points > 0) {
                    problems.Add(
                        "scans with NaN/Inf points (removed)",
                        where + ": " + std::to_string(event.removed_nonfinite_points) + " points");
                }
                if (event.scan.empty()) problems.Add("empty scans", where);
                if (!event.scan.has_power)
                    problems.Add("scans without a power field (unit weights)", where);
                if (!event.scan.empty()) {
                    ++scans_with_points;
                    planar_scans += (event.scan.xyz_radar.row(2).array() == 0.0).all();
                    min_doppler = std::min(min_doppler, event.scan.doppler_mps.minCoeff());
                    max_doppler = std::max(max_doppler, event.scan.doppler_mps.maxCoeff());
                }
                points.push_back(static_cast<double>(event.scan.size()));
                ++scans;
                break;
            }
        }
        progress.Update(scans + bad);
    }
    progress.Finish();

    std::printf("radar scans: %zu read, %zu unreadable\n", scans, bad);
    if (scans > 0) {
        const double span_s = NanosToSeconds(last_ns - first_ns);
        const double median_ms = Median(intervals_ms);
        const double max_ms = intervals_ms.empty()
                                  ? 0.0
                                  : *std::max_element(intervals_ms.begin(), intervals_ms.end());
        std::printf(
            "  time span: %.3f s, scan rate %.2f Hz (median interval %.1f ms, max %.1f ms)\n",
            span_s, median_ms > 0 ? 1e3 / median_ms : 0.0, median_ms, max_ms);
        std::printf("  points per scan: min %.0f / median %.0f / max %.0f\n",
                    *std::min_element(points.begin(), points.end()), Median(points),
                    *std::max_element(points.begin(), points.end()));
        std::printf("  doppler: %.2f .. %.2f m/s\n", min_doppler, max_doppler);
        if (scans_with_points > 0 && planar_scans == scans_with_points) {
            if (config.radar.geometry == ScanGeometry::k3d)
                std::printf(
                    "  2D radar (every z is 0): no elevation, but radar.geometry is 3d, which "
                    "refuses every scan (the directions do not span 3-D): set planar or auto\n");
            else
                std::printf(
                    "  2D radar (every z is 0): no elevation (radar.geometry %s). The "
                    "ego-velocity is fitted in the plane (v_x, v_y), the yaw rate comes from the "
                    "vehicle model%s, poses are SE(2) with z, roll and pitch held, and dorado map "
                    "registers x, y and yaw only\n",
                    ToString(config.radar.geometry),
                    config.vehicle.model == VehicleModel::kUnconstrained
                        ? " (unconstrained here: from the gyro only)"
                        : " (or a gyro)");
        } else if (planar_scans > 0) {
            std::printf("  scans with every z = 0: %zu of %zu (a 2D radar's would be all)\n",
                        planar_scans, scans_with_points);
        }
        if (median_ms > 0) {
            for (std::size_t i = 0; i < intervals_ms.size(); ++i) {
                if (intervals_ms[i] > 5.0 * median_ms) {
                    char text[96];
                    std::snprintf(text, sizeof(text), "%.2f s without a scan before scan %zu",
                                  intervals_ms[i] * 1e-3, interval_ends[i]);
                    problems.Add("gaps longer than 5 scan intervals", text);
                }
            }
        }
    }
    if (has_imu_topic || imu > 0) std::printf("imu samples: %zu\n", imu);
    if (gt > 0) std::printf("ground-truth poses in the bag: %zu\n", gt);
    if (config.reader == io::ReaderKind::kRadarScenes ||
        config.reader == io::ReaderKind::kNuScenes) {
        if (const auto reference = io::LoadGroundTruth(config); reference && !reference->empty())
            std::printf("reference trajectory (the data set's): %zu poses, %.2f s, %.1f m\n",
                        reference->size(),
                        NanosToSeconds(reference->poses().back().stamp_ns -
                                       reference->poses().front().stamp_ns),
                        reference->PathLength());
    }
    PrintRadars(config, problems);
    problems.Print();
    // A radar whose folder is refused (as the first radar's above) or cannot be read: exit 1;
    // the other problems are reported, the scans they name skipped.
    return problems.Has("radars that cannot be read") ||
                   problems.Has("radars whose scan files do not fit the description")
               ? 1
               : 0;
}

}  // namespace

void RegisterInfoCommand(CLI::App &app) {
    auto *cmd = app.add_subcommand(
        "info", "Print what a dataset holds: topics, scan rate, points per scan, fields, problems");
    auto dataset = std::make_shared<std::string>();
    auto data_dir = std::make_shared<std::string>();
    auto choice = std::make_shared<io::DatasetChoice>();
    cmd->add_option(
           "DATASET", *dataset,
           "dataset description (.yaml), a recording (ROS1 .bag, rosbag2 .db3 or .mcap, or a "
           "rosbag2 folder), or a folder with dataset.yaml")
        ->required();
    AddDataOption(cmd, *data_dir);
    AddDatasetChoiceOptions(*cmd, *choice);
    cmd->callback([dataset, data_dir, choice]() {
        const int code = RunInfo(*dataset, *data_dir, *choice);
        if (code != 0) throw CLI::RuntimeError(code);
    });
}

}  // namespace dorado::apps
