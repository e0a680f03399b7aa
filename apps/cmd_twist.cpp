// `dorado twist DATASET --out DIR`: the vehicle's planar twist (v_x, v_y, yaw rate) from every
// radar of a dataset's `radars:` list (several 2D radars on one vehicle), each radar's scan at its
// own time: a Kalman filter on the base twist updated by each radar's own ego-velocity at its
// stamp (odometry::PlanarTwistFilter; radars at different places observe the yaw rate together,
// Kellner et al. ICRA 2014, without pairing scans of different instants), dead-reckoned into a
// trajectory. Next to it, the first radar's own kinematic twist (eq. 5 in the plane).
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.hpp"
#include "dorado/config/odometry_config.hpp"
#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/core/time.hpp"
#include "dorado/core/trajectory.hpp"
#include "dorado/io/atomic_file.hpp"
#include "dorado/io/dataset.hpp"
#include "dorado/io/trajectory_io.hpp"
#include "dorado/odometry/planar_ego_velocity.hpp"
#include "dorado/odometry/planar_kinematic_model.hpp"
#include "dorado/odometry/planar_twist_filter.hpp"
#include "multi_radar_map.hpp"
#include "output_folder.hpp"
#include "preflight.hpp"
#include "progress.hpp"
#include "scan_loop.hpp"
#include "skip_log.hpp"
#include "stream_guard.hpp"

namespace dorado::apps {
namespace {

struct TwistOptions {
    std::string dataset, data, out, config;
    bool fixed_mounts = false;
    io::DatasetChoice choice;  // --scene, --sequence
};

struct RadarCounts {
    int scans = 0, ego_valid = 0;
    std::map<odometry::TwistUpdate, int> updates;
};

void RunTwist(const TwistOptions &opt) {
    const io::DatasetConfig dataset = io::ResolveDataset(opt.dataset, opt.data, opt.choice);
    if (dataset.radars.size() < 2)
        throw io::ConfigError(opt.dataset +
                              ": key 'radars': dorado twist needs a list of >= 2 radars (name, "
                              "scans_dir, timestamps_file, T_base_radar)");
    odometry::DopplerOdometryConfig config;
    if (!opt.config.empty()) config = dorado::config::LoadOdometryConfig(opt.config);
    config.ego_velocity.sensor = dataset.radar;
    const odometry::PlanarEgoVelocityEstimator estimator(config.ego_velocity);
    odometry::PlanarTwistFilterConfig filter_config;
    filter_config.calibrate_mount_yaw = !opt.fixed_mounts;
    std::vector<Eigen::Isometry3d> mounts;
    for (const io::RadarStream &radar : dataset.radars) mounts.push_back(radar.T_base_radar);
    odometry::PlanarTwistFilter filter(filter_config, dataset.vehicle.velocity_prior, mounts);
    const odometry::PlanarKinematicModel kinematic(Extrinsics{dataset.radars[0].T_base_radar},
                                                   dataset.vehicle);

    CheckBeforeWork(dataset, opt.out);
    PrepareOutputFolder(opt.out);
    std::ostringstream csv;
    csv.precision(9);
    csv << "t,radar,valid,update,v_x,v_y,omega_z,sd_v_x,sd_v_y,sd_omega_z,nis,kinematic_valid,"
           "kinematic_v_x,kinematic_omega_z\n";
    Trajectory trajectory;
    Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
    std::optional<int64_t> last_stamp;
    std::vector<RadarCounts> counts(dataset.radars.size());
    std::size_t expected = 0;
    for (std::size_t k = 0; k < dataset.radars.size(); ++k)
        expected += CountRadarMessages(io::ForRadar(dataset, k), false, "");
    auto reader = io::OpenRadars(dataset);
    Progress progress("twist", expected);
    SkipLog skips;
    StreamGuard guard;
    io::DatasetEvent event;
    std::size_t scans = 0, valid = 0;
    while (guard.Next(*reader, event)) {
        if (event.kind == io::DatasetEvent::Kind::kBadScan) {
            ++scans;
            skips.Add(event.scan_index, "unreadable scan",
                      "radar " + dataset.radars[event.radar].name + ": " + event.problem);
        }
        if (event.kind != io::DatasetEvent::Kind::kRadarScan) continue;
        progress.Update(++scans);
        const int64_t stamp = event.scan.stamp_ns;
        if (last_stamp && stamp < *last_stamp) {
            skips.Add(event.scan_index, "timestamp out of order",
                      "radar " + dataset.radars[event.radar].name);
            continue;
        }
        // Dead reckoning: the interval since the previous scan (any radar's) at the twist before
        // this scan's update (the filter's estimate over that interval).
        if (last_stamp)
            T_world_base =
                T_world_base * ExpSE3(filter.MotionOver(NanosToSeconds(stamp - *last_stamp)));
        last_stamp = stamp;
        const odometry::EgoVelocityResult ego = estimator.Estimate(event.scan);
        const odometry::TwistUpdate update = filter.Update(stamp, event.radar, ego);
        RadarCounts &c = counts[event.radar];
        ++c.scans;
        c.ego_valid += ego.valid();
        c.updates[update]++;
        const bool ok = filter.covariance()(2, 2) < 0.01;  // the yaw rate known to ~6 deg/s
        valid += ok;
        if (event.radar == 0) trajectory.Append(stamp, T_world_base);
        odometry::VehicleMotion motion;
        const bool kinematic_valid = event.radar == 0 && ego.valid();
        if (kinematic_valid) motion = kinematic.Motion(ego.v_radar_mps, ego.cov_v_radar);
        const Eigen::Vector3d x = filter.twist();
        const Eigen::Matrix3d &P = filter.covariance();
        csv << NanosToSeconds(stamp) << ',' << event.radar << ',' << ok << ','
            << odometry::ToString(update) << ',' << x(0) << ',' << x(1) << ',' << x(2) << ','
            << std::sqrt(P(0, 0)) << ',' << std::sqrt(P(1, 1)) << ',' << std::sqrt(P(2, 2)) << ','
            << filter.last_nis() << ',' << kinematic_valid << ',' << motion.v_base_mps.x() << ','
            << motion.omega_base_radps.z() << '\n';
    }
    progress.Finish();
    skips.PrintSummary();
    io::WriteFileAtomically(opt.out + "/twist.csv", [&](std::ostream &os) { os << csv.str(); });
    io::WriteTum(opt.out + "/trajectory.tum", trajectory);
    WriteCalibratedMounts(opt.out, dataset, filter);
    nlohmann::json radars = nlohmann::json::array();
    for (std::size_t k = 0; k < dataset.radars.size(); ++k)
        radars.push_back({{"name", dataset.radars[k].name},
                          {"scans", counts[k].scans},
                          {"ego_velocity_valid", counts[k].ego_valid},
                          {"twist_updates", CountsByKey(counts[k].updates)}});
    for (std::size_t k = 0; k < dataset.radars.size(); ++k)
        radars[k].update(MountRecord(filter, k));
    nlohmann::json summary = {{"dataset", dataset.name},
                              {"radars", radars},
                              {"scans", scans},
                              {"scans_valid", valid},
                              {"skip_reasons", skips.Counts()},
                              {"skipped", skips.Scans()},
                              {"path_length_m", trajectory.PathLength()}};
    WriteSummary(opt.out, summary);
    std::fprintf(stderr, "twist: %zu scans of %zu radars, %zu with a known yaw rate -> %s\n", scans,
                 dataset.radars.size(), valid, opt.out.c_str());
    guard.ThrowIfStopped("twist", scans, opt.out);
}

}  // namespace

void RegisterTwistCommand(CLI::App &app) {
    auto opt = std::make_shared<TwistOptions>();
    auto *cmd = app.add_subcommand(
        "twist",
        "The vehicle's planar twist from several 2D radars' Doppler, each radar at its own time "
        "(a Kalman filter on the twist): twist.csv, trajectory.tum, summary.json; needs the "
        "dataset's radars: list");
    cmd->add_option("DATASET", opt->dataset, "dataset description (.yaml) with radars:")
        ->required();
    AddDataOption(cmd, opt->data);
    cmd->add_option("--out", opt->out, "output folder")->required();
    AddDatasetChoiceOptions(*cmd, opt->choice);
    cmd->add_option("--config", opt->config, "odometry settings (its ego_velocity section)");
    cmd->add_flag("--fixed-mounts", opt->fixed_mounts,
                  "keep the published mounts (default: each radar's mount yaw is estimated while "
                  "running, reported in summary.json)");
    cmd->callback([opt] { RunTwist(*opt); });
}

}  // namespace dorado::apps
