#include "multi_radar_map.hpp"

#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/frontend/multi_radar_front_end.hpp"
#include "dorado/io/atomic_file.hpp"
#include "dorado/io/dataset.hpp"
#include "loop_outputs.hpp"
#include "map_outputs.hpp"
#include "output_folder.hpp"
#include "plausibility.hpp"
#include "progress.hpp"
#include "reference_path.hpp"
#include "scan_loop.hpp"
#include "skip_log.hpp"
#include "stream_guard.hpp"

namespace dorado::apps {
namespace {

// One radar's share of a run, for summary.json.
struct RadarCounts {
    int scans = 0, skipped = 0, ego_valid = 0;
    std::map<odometry::TwistUpdate, int> updates;
};

std::vector<Eigen::Isometry3d> Mounts(const io::DatasetConfig &dataset) {
    std::vector<Eigen::Isometry3d> mounts;
    for (const io::RadarStream &radar : dataset.radars) mounts.push_back(radar.T_base_radar);
    return mounts;
}

}  // namespace

nlohmann::json MountRecord(const odometry::PlanarTwistFilter &filter, std::size_t k) {
    return {{"mount_yaw_calibrated", filter.mount_yaw_sigma_rad(k) > 0.0},
            {"mount_yaw_offset_deg", RadToDeg(filter.mount_yaw_offset_rad(k))},
            {"mount_yaw_sigma_deg", RadToDeg(filter.mount_yaw_sigma_rad(k))}};
}

void WriteCalibratedMounts(const std::string &out_dir, const io::DatasetConfig &dataset,
                           const odometry::PlanarTwistFilter &filter) {
    io::WriteFileAtomically(out_dir + "/mounts.yaml", [&](std::ostream &os) {
        os.precision(10);
        const bool folder = dataset.reader == io::ReaderKind::kFolder;
        os << "# The radars' mounts as calibrated by this run (the published yaw plus the "
              "estimated "
              "offset,\n# 1-sigma in the comment): "
           << (folder ? "paste into the dataset description's radars: list."
                      : "the data set's own reader takes its published mounts (each run\n# "
                        "calibrates again); a folder description of the radars takes these.")
           << "\nradars:\n";
        for (std::size_t k = 0; k < dataset.radars.size(); ++k) {
            const io::RadarStream &radar = dataset.radars[k];
            const Eigen::Isometry3d T = filter.T_base_radar(k);
            const Eigen::Vector3d rpy = RollPitchYaw(T.linear());
            const Eigen::Vector3d t = T.translation();
            os << "  - name: " << radar.name << "  # yaw offset "
               << RadToDeg(filter.mount_yaw_offset_rad(k)) << " +- "
               << RadToDeg(filter.mount_yaw_sigma_rad(k)) << " deg\n";
            if (!radar.scans_dir.empty())  // a folder's radar (the data sets' own: no files)
                os << "    scans_dir: " << radar.scans_dir << "\n"
                   << "    timestamps_file: " << radar.timestamps_file << "\n";
            os << "    T_base_radar: {translation_m: [" << t.x() << ", " << t.y() << ", " << t.z()
               << "], rotation_rpy_deg: [" << RadToDeg(rpy.x()) << ", " << RadToDeg(rpy.y()) << ", "
               << RadToDeg(rpy.z()) << "]}\n";
        }
    });
}

void RunMultiRadarMap(const io::DatasetConfig &dataset, const frontend::FrontEndConfig &config,
                      const loops::LoopClosureConfig &loop_config,
                      const odometry::PlanarTwistFilterConfig &twist_filter,
                      const std::string &out_dir, bool accept_implausible) {
    frontend::MultiRadarFrontEnd front_end(config, Mounts(dataset), dataset.extrinsics.T_base_imu,
                                           dataset.vehicle, twist_filter);
    PrepareOutputFolder(out_dir);
    auto reader = io::OpenRadars(dataset);
    std::size_t expected = 0;
    for (std::size_t k = 0; k < dataset.radars.size(); ++k)
        expected += CountRadarMessages(io::ForRadar(dataset, k), false, "");
    Progress progress("map", expected);
    MapOutputs outputs(config.mapper.map.voxel_size_m);
    std::optional<LoopOutputs> loop_closure;
    if (loop_config.enabled) loop_closure.emplace(loop_config);
    SkipLog skips;
    std::vector<RadarCounts> counts(dataset.radars.size());
    std::size_t scans = 0, sweeps = 0;
    long long nonfinite = 0;
    double radars_per_sweep = 0.0;
    PlausibilityWatch plausibility(dataset.radar.doppler_unambiguous_mps);
    StreamGuard guard;  // Ctrl-C or a reader error mid-stream: stop, write what was done
    io::DatasetEvent event;
    while (guard.Next(*reader, event)) {
        if (event.kind == io::DatasetEvent::Kind::kImu) front_end.AddImu(event.imu);
        const std::string radar_name =
            event.radar < dataset.radars.size() ? dataset.radars[event.radar].name : "?";
        if (event.kind == io::DatasetEvent::Kind::kBadScan) {
            ++scans;
            ++counts[event.radar].skipped;
            skips.Add(event.scan_index, "unreadable scan",
                      "radar " + radar_name + ": " + event.problem);
        }
        if (event.kind != io::DatasetEvent::Kind::kRadarScan) continue;
        ++scans;
        RadarCounts &c = counts[event.radar];
        ++c.scans;
        nonfinite += event.removed_nonfinite_points;
        const frontend::RadarScanStep step = front_end.Process(event.radar, event.scan);
        progress.Update(scans);
        if (!step.accepted) {
            ++c.skipped;
            skips.Add(event.scan_index, "timestamp out of order",
                      "radar " + radar_name + ": " + step.skip_reason);
            continue;
        }
        c.ego_valid += step.ego.valid();
        plausibility.AddPoints(event.scan);
        plausibility.AddSpeed(event.stamp_ns, step.ego.valid(), step.ego.v_radar_mps.norm());
        c.updates[step.twist_update]++;
        if (step.sweep) {
            outputs.Add(*step.sweep);
            if (loop_closure) loop_closure->Add(step.sweep->registration.written);
            ++sweeps;
            radars_per_sweep += step.sweep_radars;
        }
    }
    progress.Finish();
    skips.PrintSummary();
    guard.ThrowIfNoScanUsed(sweeps, reader->source());

    const nlohmann::json loop_summary =
        FinishMapRun(out_dir, dataset, front_end.Finish(), front_end.trajectory(), outputs,
                     loop_closure ? &*loop_closure : nullptr);
    WriteCalibratedMounts(out_dir, dataset, front_end.twist_filter());
    nlohmann::json radars = nlohmann::json::array();
    for (std::size_t k = 0; k < dataset.radars.size(); ++k) {
        const RadarCounts &c = counts[k];
        radars.push_back({{"name", dataset.radars[k].name},
                          {"scans", c.scans},
                          {"skipped", c.skipped},
                          {"ego_velocity_valid", c.ego_valid},
                          {"twist_updates", CountsByKey(c.updates)}});
        radars.back().update(MountRecord(front_end.twist_filter(), k));
    }
    nlohmann::json summary = MapRunSummary(dataset.name, config, guard.stopped());
    summary["loop_closure"] = loop_summary;
    summary.update({{"scans", scans},
                    {"scans_registered", sweeps},
                    {"sweeps", sweeps},
                    {"radars_per_sweep_mean", sweeps > 0 ? radars_per_sweep / double(sweeps) : 0.0},
                    {"radars", radars},
                    {"skip_reasons", skips.Counts()},
                    {"skipped", skips.Scans()},
                    {"nonfinite_points_removed", nonfinite},
                    {"radar_geometry", "planar"},
                    {"path_length_m", front_end.trajectory().PathLength()}});
    summary.update(outputs.Summary());
    const std::vector<std::string> implausible =
        plausibility.Problems(sweeps, static_cast<std::size_t>(outputs.fallbacks()),
                              "fell back to the prior", front_end.trajectory().PathLength());
    summary.update(PlausibilityRecord(implausible, plausibility, accept_implausible));
    WriteSummary(out_dir, summary);
    std::fprintf(stderr,
                 "map: %zu scans of %zu radars, %zu sweeps (%.2f radars each), %d fell back to "
                 "the prior, %.2f ms/sweep, path %.1f m -> %s\n",
                 scans, dataset.radars.size(), sweeps,
                 sweeps > 0 ? radars_per_sweep / double(sweeps) : 0.0, outputs.fallbacks(),
                 outputs.mean_time_ms(), front_end.trajectory().PathLength(), out_dir.c_str());
    guard.ThrowIfStopped("map", scans, out_dir);
    EndIfImplausible(implausible, "map", out_dir, accept_implausible);
}

}  // namespace dorado::apps
