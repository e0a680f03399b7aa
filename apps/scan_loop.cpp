#include "scan_loop.hpp"

#include <cstdio>

#include "dorado/io/atomic_file.hpp"
#include "dorado/io/closest_name.hpp"
#include "dorado/mapping/motion_prior.hpp"

namespace dorado::apps {

void ScanLoop::Run(io::DatasetReader &reader, StreamGuard &guard, Progress &progress,
                   const OnScan &on_scan) {
    io::DatasetEvent event;
    while (guard.Next(reader, event)) {
        if (event.kind == io::DatasetEvent::Kind::kImu) front_end_.AddImu(event.imu);
        if (event.kind == io::DatasetEvent::Kind::kBadScan) {
            ++scans_;
            skips_.Add(event.scan_index, "unreadable scan", event.problem);
        }
        if (event.kind != io::DatasetEvent::Kind::kRadarScan) continue;
        ++scans_;
        const frontend::FrontEndResult result = front_end_.Process(event.scan);
        progress.Update(scans_);
        if (!result.accepted) {
            skips_.Add(event.scan_index, "timestamp out of order", result.skip_reason);
            continue;
        }
        Warn(event, result);
        if (result.odometry.planar_detected) {
            std::fprintf(stderr,
                         "scan %zu: 2D radar (every z is 0): planar mode: the ego-velocity in the "
                         "radar's plane (v_x, v_y), the yaw rate from the vehicle model, poses in "
                         "SE(2) with z, roll and pitch held (set radar.geometry: planar in the "
                         "dataset description to say so, 3d to refuse)\n",
                         event.scan_index);
        }
        planar_ = planar_ || result.odometry.planar;
        nonfinite_points_ += event.removed_nonfinite_points;
        ++used_;
        on_scan(event, result);
    }
    progress.Finish();
    skips_.PrintSummary();
}

// What was done about a scan without a point, or after a gap: the mapper's prior stood in, or
// the odometry integrated a twist.
void ScanLoop::Warn(const io::DatasetEvent &event, const frontend::FrontEndResult &result) {
    const bool mapping = front_end_.config().run_mapper;
    const std::string prior = mapping::ToString(result.prior_used);
    if (event.scan.empty()) {
        const std::string done = mapping ? ": pose from the " + prior + " prior"
                                 : result.odometry.used_fallback
                                     ? ": " + result.odometry.fallback_reason
                                     : std::string();
        skips_.WarnNoFinitePoints(event.scan_index, event.removed_nonfinite_points, done);
    }
    if (result.dt_s > 0.0 && gaps_.IsGap(result.dt_s)) {
        skips_.Warn(
            event.scan_index, "gap",
            gaps_.Describe(result.dt_s) + (mapping ? "; the " + prior + " prior spans it"
                                                   : "; integrated this scan's twist over it"));
    }
}

bool HasImu(const io::DatasetConfig &dataset) {
    if (dataset.reader == io::ReaderKind::kRosbag) return !dataset.rosbag.imu_topic.empty();
    return !dataset.imu.path.empty();
}

const char *ImuKey(const io::DatasetConfig &dataset) {
    return dataset.reader == io::ReaderKind::kRosbag ? "rosbag.imu_topic" : "imu.path";
}

std::string ImuSource(const io::DatasetConfig &dataset) {
    if (dataset.reader == io::ReaderKind::kRosbag)
        return dataset.rosbag.path + " (rosbag.imu_topic " + dataset.rosbag.imu_topic + ")";
    return dataset.imu.path + " (imu.path)";
}

std::string DatasetFile(const io::DatasetConfig &dataset, const std::string &arg) {
    return dataset.config_path.empty() ? arg : dataset.config_path;
}

nlohmann::json ReportRadarsUsed(const io::DatasetConfig &dataset, const std::string &arg,
                                const std::string &command) {
    if (dataset.radars.size() < 2) return nullptr;
    std::string names;
    for (const io::RadarStream &radar : dataset.radars)
        names += (names.empty() ? "" : ", ") + radar.name;
    // A folder's one radar is `folder:`; a data set's own reader's the first of its radars.
    const bool folder = dataset.reader == io::ReaderKind::kFolder;
    const std::string used = folder ? dataset.folder.scans_dir : dataset.radars.front().name;
    std::fprintf(stderr,
                 "%s: warning: %s: %zu radars (%s); dorado %s reads only the %s radar (%s): the "
                 "others are not used (--radars NAME picks another; every radar: dorado map "
                 "--radars all, dorado twist)\n",
                 command.c_str(), DatasetFile(dataset, arg).c_str(), dataset.radars.size(),
                 names.c_str(), command.c_str(), folder ? "`folder:` + `extrinsics:`" : "first",
                 used.c_str());
    return {{"radars_listed", dataset.radars.size()},
            {"radars_used", nlohmann::json::array({used})}};
}

io::DatasetConfig SelectRadar(const io::DatasetConfig &dataset, const std::string &choice,
                              bool all_allowed) {
    if (choice.empty() || choice == "first") return dataset;
    std::string names;
    std::vector<std::string> known{"first"};
    if (all_allowed) known.push_back("all");
    for (std::size_t k = 0; k < dataset.radars.size(); ++k) {
        if (dataset.radars[k].name == choice) return io::ForRadar(dataset, k);
        names += (names.empty() ? "" : ", ") + dataset.radars[k].name;
        known.push_back(dataset.radars[k].name);
    }
    const std::string closest = io::ClosestName(choice, known);
    throw io::ConfigError("--radars " + choice + ": " +
                          (names.empty()
                               ? "the dataset has no radars: list"
                               : "no such radar in the dataset's radars: list (" + names + ")") +
                          (closest.empty() ? "" : "; did you mean '" + closest + "'?"));
}

void WriteMaskFile(const std::string &out_dir, std::size_t scan_index, int64_t stamp_ns,
                   const std::string &legend, const std::vector<int> &labels) {
    char name[32];
    std::snprintf(name, sizeof(name), "/masks/%06zu.txt", scan_index);
    io::WriteFileAtomically(out_dir + name, [&](std::ostream &os) {
        os << "# stamp_ns " << stamp_ns << ", one label per point in input order: " << legend
           << '\n';
        for (const int label : labels) os << label << '\n';
    });
}

void AddStreamCounts(const ScanLoop &loop, nlohmann::json &summary) {
    summary["skip_reasons"] = loop.skips().Counts();
    summary["skipped"] = loop.skips().Scans();
    summary["warnings"] = loop.skips().WarningCounts();
    summary["warned"] = loop.skips().Warnings();
    summary["nonfinite_points_removed"] = loop.nonfinite_points();
    if (loop.planar()) summary["radar_geometry"] = "planar";
}

void WriteSummary(const std::string &out_dir, const nlohmann::json &summary) {
    io::WriteFileAtomically(out_dir + "/summary.json",
                            [&](std::ostream &os) { os << summary.dump(2) << '\n'; });
}

}  // namespace dorado::apps
