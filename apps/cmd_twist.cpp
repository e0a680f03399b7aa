// `dorado twist DATASET --out DIR`: the vehicle's planar twist (v_x, v_y, yaw rate) from every
// radar's Doppler jointly (Kellner et al. ICRA 2014), for a dataset description with a `radars:`
// list (several 2D radars on one vehicle). The first radar's scans set the times; each other
// radar's nearest scan within --max-dt joins. Next to it, the first radar's own kinematic twist
// (eq. 5 in the plane), for comparison.
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.hpp"
#include "dorado/config/odometry_config.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/core/time.hpp"
#include "dorado/core/trajectory.hpp"
#include "dorado/io/atomic_file.hpp"
#include "dorado/io/dataset.hpp"
#include "dorado/io/trajectory_io.hpp"
#include "dorado/odometry/multi_radar_twist.hpp"
#include "dorado/odometry/planar_ego_velocity.hpp"
#include "dorado/odometry/planar_kinematic_model.hpp"
#include "scan_loop.hpp"

namespace dorado::apps {
namespace {

struct TwistOptions {
    std::string dataset, out, config;
    double max_dt_s = 0.04;
};

struct RadarRun {
    std::string name;
    Eigen::Isometry3d T_base_radar = Eigen::Isometry3d::Identity();
    std::vector<RadarScan> scans;
    std::vector<odometry::EgoVelocityResult> egos;
};

RadarRun ReadRadar(const io::DatasetConfig &one, const std::string &name,
                   const odometry::PlanarEgoVelocityEstimator &estimator) {
    RadarRun run;
    run.name = name;
    run.T_base_radar = one.extrinsics.T_base_radar;
    auto reader = io::OpenDataset(one);
    io::DatasetEvent event;
    while (reader->Next(event)) {
        if (event.kind != io::DatasetEvent::Kind::kRadarScan) continue;
        run.egos.push_back(estimator.Estimate(event.scan));
        run.scans.push_back(std::move(event.scan));
    }
    return run;
}

// The scan of `run` nearest to stamp_ns within max_dt_s, or -1.
long Nearest(const RadarRun &run, int64_t stamp_ns, double max_dt_s) {
    long best = -1;
    double best_dt = max_dt_s;
    for (std::size_t i = 0; i < run.scans.size(); ++i) {
        const double dt = std::abs(NanosToSeconds(run.scans[i].stamp_ns - stamp_ns));
        if (dt <= best_dt) {
            best_dt = dt;
            best = static_cast<long>(i);
        }
    }
    return best;
}

void RunTwist(const TwistOptions &opt) {
    const io::DatasetConfig dataset = io::ResolveDataset(opt.dataset);
    if (dataset.radars.size() < 2)
        throw io::ConfigError(opt.dataset +
                              ": key 'radars': dorado twist needs a list of >= 2 radars (name, "
                              "scans_dir, timestamps_file, T_base_radar)");
    odometry::DopplerOdometryConfig config;
    if (!opt.config.empty()) config = dorado::config::LoadOdometryConfig(opt.config);
    config.ego_velocity.sensor = dataset.radar;
    const odometry::PlanarEgoVelocityEstimator estimator(config.ego_velocity);
    std::vector<RadarRun> radars;
    for (std::size_t k = 0; k < dataset.radars.size(); ++k)
        radars.push_back(ReadRadar(io::ForRadar(dataset, k), dataset.radars[k].name, estimator));
    const RadarRun &reference = radars.front();
    const odometry::PlanarKinematicModel kinematic(Extrinsics{reference.T_base_radar},
                                                   dataset.vehicle);

    io::MakeDirectories(opt.out);
    std::ostringstream csv;
    csv.precision(9);
    csv << "t,valid,v_x,v_y,omega_z,sd_v_x,sd_v_y,sd_omega_z,radars_used,points_used,"
           "residual_sigma_mps,kinematic_valid,kinematic_v_x,kinematic_omega_z\n";
    Trajectory trajectory;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    Eigen::Vector3d last = Eigen::Vector3d::Zero();
    int valid = 0;
    double radars_used = 0.0;
    for (std::size_t i = 0; i < reference.scans.size(); ++i) {
        const int64_t stamp = reference.scans[i].stamp_ns;
        std::vector<odometry::RadarObservation> observations;
        observations.push_back({&reference.scans[i], reference.T_base_radar, &reference.egos[i]});
        for (std::size_t k = 1; k < radars.size(); ++k) {
            const long j = Nearest(radars[k], stamp, opt.max_dt_s);
            if (j >= 0)
                observations.push_back(
                    {&radars[k].scans[j], radars[k].T_base_radar, &radars[k].egos[j]});
        }
        const odometry::PlanarTwist twist = odometry::EstimatePlanarTwist(observations);
        const odometry::EgoVelocityResult &ego = reference.egos[i];
        odometry::VehicleMotion motion;
        if (ego.valid()) motion = kinematic.Motion(ego.v_radar_mps, ego.cov_v_radar);
        if (i > 0) {  // integrate the previous interval with the newest twist
            const double dt = NanosToSeconds(stamp - reference.scans[i - 1].stamp_ns);
            Vector6d xi = Vector6d::Zero();
            xi << last(0) * dt, last(1) * dt, 0.0, 0.0, 0.0, last(2) * dt;
            T = T * ExpSE3(xi);
        }
        if (twist.valid()) last = twist.twist;
        trajectory.Append(stamp, T);
        valid += twist.valid();
        radars_used += twist.radars_used;
        csv << NanosToSeconds(stamp) << ',' << twist.valid() << ',' << twist.twist(0) << ','
            << twist.twist(1) << ',' << twist.twist(2) << ',' << std::sqrt(twist.covariance(0, 0))
            << ',' << std::sqrt(twist.covariance(1, 1)) << ',' << std::sqrt(twist.covariance(2, 2))
            << ',' << twist.radars_used << ',' << twist.points_used << ','
            << twist.residual_sigma_mps << ',' << ego.valid() << ',' << motion.v_base_mps.x() << ','
            << motion.omega_base_radps.z() << '\n';
    }
    io::WriteFileAtomically(opt.out + "/twist.csv", [&](std::ostream &os) { os << csv.str(); });
    io::WriteTum(opt.out + "/trajectory.tum", trajectory);
    const std::size_t n = reference.scans.size();
    nlohmann::json summary = {{"dataset", dataset.name},
                              {"radars", dataset.radars.size()},
                              {"scans", n},
                              {"scans_valid", valid},
                              {"radars_used_mean", n > 0 ? radars_used / n : 0.0},
                              {"path_length_m", trajectory.PathLength()}};
    WriteSummary(opt.out, summary);
    std::fprintf(stderr,
                 "twist: %zu scans of %s, %d with a joint twist (%.2f radars each), -> %s\n", n,
                 reference.name.c_str(), valid, n > 0 ? radars_used / n : 0.0, opt.out.c_str());
}

}  // namespace

void RegisterTwistCommand(CLI::App &app) {
    auto opt = std::make_shared<TwistOptions>();
    auto *cmd = app.add_subcommand(
        "twist",
        "The vehicle's planar twist from several 2D radars' Doppler jointly (Kellner et al. "
        "2014): twist.csv, trajectory.tum, summary.json; needs the dataset's radars: list");
    cmd->add_option("DATASET", opt->dataset, "dataset description (.yaml) with radars:")
        ->required();
    cmd->add_option("--out", opt->out, "output folder")->required();
    cmd->add_option("--config", opt->config, "odometry settings (its ego_velocity section)");
    cmd->add_option("--max-dt", opt->max_dt_s,
                    "the other radars' scans within this many seconds of the first's [s]");
    cmd->callback([opt] { RunTwist(*opt); });
}

}  // namespace dorado::apps
