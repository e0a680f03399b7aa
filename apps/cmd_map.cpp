// `dorado map DATASET --prior P --out DIR`: radar scan-to-map mapping with a motion prior (paper
// section IV-C), the Doppler estimator's dynamic-point mask, a Doppler-aware registration and
// the fixed-lag smoother whose poses are written, then closed into loops (loop_outputs.hpp).
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>

#include "commands.hpp"
#include "dorado/config/map_config.hpp"
#include "dorado/config/odometry_config.hpp"
#include "dorado/frontend/radar_front_end.hpp"
#include "dorado/io/atomic_file.hpp"
#include "dorado/io/dataset.hpp"
#include "loop_outputs.hpp"
#include "map_outputs.hpp"
#include "multi_radar_map.hpp"
#include "output_folder.hpp"
#include "plausibility.hpp"
#include "preflight.hpp"
#include "progress.hpp"
#include "reference_path.hpp"
#include "scan_loop.hpp"
#include "stream_guard.hpp"

namespace dorado::apps {
namespace {

struct MapOptions {
    std::string dataset, out, config, odometry_config, prior = "doppler", radars = "all";
    std::string data;  // --data DIR
    bool no_mask = false, masks = false, fixed_mounts = false, accept_implausible = false;
    bool no_loops = false;
    double inject_false_loops = 0.0;  // robustness test: a fraction of submaps gets a false loop
    io::DatasetChoice choice;         // --scene, --sequence
};

// DIR/masks/NNNNNN.txt: what the map used of each point (the odometry's labels, and 3 for the
// points the mover rules kept out although the Doppler called them static).
void WriteMapMask(const std::string &out_dir, std::size_t scan_index,
                  const frontend::FrontEndResult &r) {
    const mapping::PointMask &dropped = r.registration.mover_dropped;
    std::vector<int> labels;
    labels.reserve(r.odometry.ego.labels.size());
    for (std::size_t i = 0; i < r.odometry.ego.labels.size(); ++i) {
        const auto k = static_cast<Eigen::Index>(i);
        labels.push_back(
            k < dropped.size() && dropped(k) ? 3 : static_cast<int>(r.odometry.ego.labels[i]));
    }
    WriteMaskFile(out_dir, scan_index, r.stamp_ns,
                  "0 static, 1 dynamic, 2 filtered, 3 kept out as a mover's (near a moving point "
                  "or where something moved)",
                  labels);
}

// The front end's settings from the flags and the two YAML files.
frontend::FrontEndConfig FrontEndConfigOf(const MapOptions &opt,
                                          const dorado::config::MapCommandConfig &map_config) {
    frontend::FrontEndConfig config;
    if (!opt.odometry_config.empty())
        config.odometry = dorado::config::LoadOdometryConfig(opt.odometry_config);
    config.mapper = map_config.mapper;
    config.prior_noise = map_config.prior;
    config.prior = dorado::config::ParsePriorKindKey(opt.prior, "--prior");
    config.use_mask = !opt.no_mask;
    return config;
}

void RunMap(const MapOptions &opt) {
    const io::DatasetConfig dataset =
        opt.radars == "all"
            ? io::ResolveDataset(opt.dataset, opt.data, opt.choice)
            : SelectRadar(io::ResolveDataset(opt.dataset, opt.data, opt.choice), opt.radars, true);
    const dorado::config::MapCommandConfig map_config =
        opt.config.empty() ? dorado::config::MapCommandConfig{}
                           : dorado::config::LoadMapConfig(opt.config);
    frontend::FrontEndConfig config = FrontEndConfigOf(opt, map_config);
    loops::LoopClosureConfig loop_config = map_config.loop_closure;
    if (opt.no_loops) loop_config.enabled = false;
    loop_config.injected_false_fraction = opt.inject_false_loops;
    loop_config.Validate();
    config.odometry.ego_velocity.sensor = dataset.radar;  // the radar: noise, ambiguity
    const bool needs_imu = mapping::NeedsImu(config.prior);
    if (needs_imu && !HasImu(dataset))
        throw io::ConfigError(DatasetFile(dataset, opt.dataset) + ": key '" + ImuKey(dataset) +
                              "': --prior " + opt.prior + " needs an IMU");
    StateAssumptions(dataset, opt.dataset, "map");
    if (dataset.radars.size() >= 2 && opt.radars == "all") {
        if (opt.masks)
            throw io::ConfigError(
                "--masks: per-point masks are written for one radar; with the "
                "dataset's radars: list add --radars first (or a radar's name)");
        odometry::PlanarTwistFilterConfig twist_filter;
        twist_filter.calibrate_mount_yaw = !opt.fixed_mounts;
        CheckBeforeWork(dataset, opt.out);
        RunMultiRadarMap(dataset, config, loop_config, twist_filter, opt.out,
                         opt.accept_implausible);
        return;
    }
    const nlohmann::json radars_used = ReportRadarsUsed(dataset, opt.dataset, "map");
    frontend::RadarFrontEnd front_end(config, dataset.extrinsics, dataset.vehicle);
    const std::size_t expected = CountRadarMessages(dataset, needs_imu, "--prior " + opt.prior);
    CheckBeforeWork(dataset, opt.out);
    PrepareOutputFolder(opt.out);
    if (opt.masks) io::MakeDirectories(opt.out + "/masks");

    auto reader = io::OpenDataset(dataset);
    Progress progress("map", expected);
    MapOutputs outputs(config.mapper.map.voxel_size_m);
    PlausibilityWatch plausibility(dataset.radar.doppler_unambiguous_mps);
    std::optional<LoopOutputs> loop_closure;
    if (loop_config.enabled) loop_closure.emplace(loop_config);
    ScanLoop loop(front_end);
    StreamGuard guard;  // Ctrl-C or a reader error mid-stream: stop, write what was done
    loop.Run(*reader, guard, progress,
             [&](const io::DatasetEvent &event, const frontend::FrontEndResult &r) {
                 outputs.Add(r);
                 plausibility.AddPoints(event.scan);
                 plausibility.AddSpeed(event.stamp_ns, r.odometry.ego.valid(),
                                       r.odometry.ego.v_radar_mps.norm());
                 if (loop_closure) loop_closure->Add(r.registration.written);
                 if (opt.masks && r.accepted) WriteMapMask(opt.out, event.scan_index, r);
             });
    guard.ThrowIfNoScanUsed(loop.used(), reader->source());

    const nlohmann::json loop_summary =
        FinishMapRun(opt.out, dataset, front_end.Finish(), front_end.trajectory(), outputs,
                     loop_closure ? &*loop_closure : nullptr);
    nlohmann::json summary = MapRunSummary(dataset.name, config, guard.stopped());
    summary["loop_closure"] = loop_summary;
    summary.update({{"scans", loop.scans()},
                    {"scans_registered", loop.used()},
                    {"scans_skipped", loop.scans() - loop.used()},
                    {"path_length_m", front_end.trajectory().PathLength()}});
    if (!radars_used.is_null()) summary["radars"] = radars_used;
    AddStreamCounts(loop, summary);
    summary.update(outputs.Summary());
    const std::vector<std::string> implausible =
        plausibility.Problems(loop.used(), static_cast<std::size_t>(outputs.fallbacks()),
                              "fell back to the prior", front_end.trajectory().PathLength());
    summary.update(PlausibilityRecord(implausible, plausibility, opt.accept_implausible));
    WriteSummary(opt.out, summary);
    std::fprintf(stderr,
                 "map: %zu scans, %zu registered, %d fell back to the prior, %.2f ms/scan, path "
                 "%.1f m -> %s\n",
                 loop.scans(), loop.used(), outputs.fallbacks(), outputs.mean_time_ms(),
                 front_end.trajectory().PathLength(), opt.out.c_str());
    guard.ThrowIfStopped("map", loop.scans(), opt.out);
    EndIfImplausible(implausible, "map", opt.out, opt.accept_implausible);
}

}  // namespace

void RegisterMapCommand(CLI::App &app) {
    auto opt = std::make_shared<MapOptions>();
    auto *cmd = app.add_subcommand("map",
                                   "Radar scan-to-map mapping with a motion prior, the Doppler "
                                   "dynamic-point mask, a Doppler-aware registration and a "
                                   "fixed-lag smoother whose poses are written and mapped.");
    cmd->add_option(
           "DATASET", opt->dataset,
           "dataset description (.yaml), or a recording (.bag, .db3, .mcap, rosbag2 folder)")
        ->required();
    AddDataOption(cmd, opt->data);
    cmd->add_option("--out", opt->out, "output folder")->required();
    AddDatasetChoiceOptions(*cmd, opt->choice);
    cmd->add_option("--prior", opt->prior,
                    "motion prior: none | constvel | imu | doppler (default) | imu+doppler");
    cmd->add_option("--config", opt->config,
                    "mapper settings (configs/mapper.yaml; every key and default: "
                    "`dorado config print mapper`)");
    cmd->add_option("--odometry-config", opt->odometry_config,
                    "Doppler estimator settings (configs/odometry.yaml; `dorado config print "
                    "odometry`)");
    cmd->add_option("--radars", opt->radars,
                    "with the dataset's radars: list: all (default: every radar into one map, "
                    "each at its own time), first (the folder: + extrinsics: radar alone) or a "
                    "radar's name (that radar alone)");
    cmd->add_flag("--fixed-mounts", opt->fixed_mounts,
                  "with several radars: keep the published mounts (default: each radar's mount "
                  "yaw is estimated while running, reported in summary.json and mounts.yaml)");
    cmd->add_flag("--no-mask", opt->no_mask, "keep the dynamic points (ablation)");
    cmd->add_flag("--no-loops", opt->no_loops,
                  "no loop closure (default: on, `loop_closure.enabled` in --config): "
                  "trajectory.tum and the map as the smoother wrote them");
    cmd->add_option("--inject-false-loops", opt->inject_false_loops,
                    "robustness test: this fraction (0..1) of the submaps gets a false loop edge "
                    "straight into the pose graph (marked in loops.csv)")
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_flag("--masks", opt->masks,
                  "write DIR/masks/NNNNNN.txt: per point 0 static, 1 dynamic, 2 filtered, 3 kept "
                  "out by the mover rules");
    AddAcceptImplausibleFlag(cmd, opt->accept_implausible);
    cmd->callback([opt] { RunMap(*opt); });
}

}  // namespace dorado::apps
