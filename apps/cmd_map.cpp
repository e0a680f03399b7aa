// `dorado map DATASET --prior P --out DIR`: radar scan-to-map mapping with a motion prior (paper
// section IV-C), the Doppler estimator's dynamic-point mask, and a Doppler-aware refinement.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "commands.hpp"
#include "dorado/core/time.hpp"
#include "dorado/io/atomic_file.hpp"
#include "dorado/io/dataset.hpp"
#include "dorado/io/trajectory_io.hpp"
#include "dorado/mapping/radar_mapper.hpp"
#include "dorado/odometry/ego_velocity.hpp"
#include "dorado/odometry/kinematic_model.hpp"
#include "map_config.hpp"
#include "map_image.hpp"
#include "odometry_config.hpp"
#include "progress.hpp"
#include "skip_log.hpp"
#include "stream_guard.hpp"

namespace dorado::apps {
namespace {

struct MapOptions {
    std::string dataset, out, config, odometry_config, prior = "doppler", refine;
    bool no_mask = false;
};

double MsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

std::string Quoted(const std::string &text) {
    std::string out = "\"";
    for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
    return out + "\"";
}

// The `doppler` prior's twist: the kinematic model's, with the estimator's covariance (eq. 7), the
// model's own error (a vehicle that slips, bounces and rolls) and the vehicle's angular-rate prior
// (KinematicModel::PlausibleTwist). The cross-covariance between v and omega is dropped (the
// prior is block-diagonal).
mapping::BaseTwist TwistOf(const odometry::VehicleTwist &t) {
    return {t.v_base_mps, t.omega_base_radps, t.covariance.topLeftCorner<3, 3>(),
            t.covariance.bottomRightCorner<3, 3>()};
}

// The `imu+doppler` prior's velocity: the gyro gives omega and v_base = v_s - omega x s, without
// the model's error; its covariance is the estimator's (eq. 7).
mapping::BaseTwist TwistOf(const odometry::VehicleMotion &m) {
    return {m.v_base_mps, m.omega_base_radps, m.cov_v_base, m.cov_omega_base};
}

void WritePcd(const std::string &path, const Eigen::Matrix3Xd &points) {
    io::WriteFileAtomically(path, [&](std::ostream &os) {
        os << "# .PCD v0.7 - dorado map (world frame)\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\n"
           << "TYPE F F F\nCOUNT 1 1 1\nWIDTH " << points.cols() << "\nHEIGHT 1\n"
           << "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << points.cols() << "\nDATA ascii\n";
        for (Eigen::Index i = 0; i < points.cols(); ++i)
            os << points(0, i) << ' ' << points(1, i) << ' ' << points(2, i) << '\n';
    });
}

void WritePly(const std::string &path, const Eigen::Matrix3Xd &points) {
    io::WriteFileAtomically(path, [&](std::ostream &os) {
        os << "ply\nformat ascii 1.0\ncomment dorado map (world frame)\nelement vertex "
           << points.cols()
           << "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
        for (Eigen::Index i = 0; i < points.cols(); ++i)
            os << points(0, i) << ' ' << points(1, i) << ' ' << points(2, i) << '\n';
    });
}

void RunMap(const MapOptions &opt) {
    const io::DatasetConfig dataset = io::ResolveDataset(opt.dataset);
    MapCommandConfig config;
    if (!opt.config.empty()) config = LoadMapConfig(opt.config);
    if (opt.refine == "none") config.mapper.refinement = mapping::Refinement::kNone;
    if (opt.refine == "ceres") config.mapper.refinement = mapping::Refinement::kCeres;
    odometry::EgoVelocityConfig ego_config;
    if (!opt.odometry_config.empty())
        ego_config = LoadOdometryConfig(opt.odometry_config).ego_velocity;
    const bool wants_imu = opt.prior == "imu" || opt.prior == "imu+doppler";
    const bool wants_doppler = opt.prior == "doppler" || opt.prior == "imu+doppler";
    const bool has_imu =
        dataset.reader == io::ReaderKind::kRosbag && !dataset.rosbag.imu_topic.empty();
    if (wants_imu && !has_imu)
        throw io::ConfigError((dataset.config_path.empty() ? opt.dataset : dataset.config_path) +
                              ": key 'rosbag.imu_topic': --prior " + opt.prior +
                              " needs an IMU topic");
    const bool use_mask = !opt.no_mask;
    std::optional<odometry::KinematicModel> kinematics;
    if (wants_doppler) kinematics.emplace(dataset.extrinsics, dataset.vehicle);
    odometry::EgoVelocityEstimator estimator(ego_config);
    mapping::RadarMapper mapper(config.mapper, dataset.extrinsics);
    mapping::LocalMap output_map(
        {config.output_voxel_m, 1, std::numeric_limits<double>::infinity()});
    io::MakeDirectories(opt.out);

    const std::size_t expected = CountRadarMessages(dataset, wants_imu, "--prior " + opt.prior);
    auto reader = io::OpenDataset(dataset);
    Progress progress("map", expected);

    Trajectory trajectory;
    std::vector<Eigen::Vector3d> positions;
    std::vector<ImuSample> imu;
    std::ostringstream csv;
    csv << "t,time_doppler_ms,time_preprocess_ms,time_registration_ms,time_refinement_ms,"
           "time_map_update_ms,time_total_ms,correspondences,fitness,fallback,fallback_reason\n";
    std::map<std::string, int> fallback_reasons, prior_substitutions;
    SkipLog skips;
    GapWatch gaps;
    Eigen::Index nonfinite_points = 0;
    std::vector<double> total_ms;
    std::size_t scans = 0, registered = 0, unmasked = 0;
    int64_t last_stamp = 0;
    double last_dt = 0.0;
    io::DatasetEvent event;
    StreamGuard guard;  // Ctrl-C or a reader error mid-stream: stop, write what was done
    while (guard.Next(*reader, event)) {
        if (event.kind == io::DatasetEvent::Kind::kImu) imu.push_back(event.imu);
        if (event.kind == io::DatasetEvent::Kind::kBadScan) {
            ++scans;
            skips.Add(event.scan_index, "unreadable scan", event.problem);
        }
        if (event.kind != io::DatasetEvent::Kind::kRadarScan) continue;
        ++scans;
        progress.Update(scans);
        const RadarScan &scan = event.scan;
        const bool first = trajectory.empty();
        if (!first && scan.stamp_ns <= last_stamp) {
            skips.Add(event.scan_index, "timestamp out of order",
                      "stamp " + std::to_string(scan.stamp_ns) +
                          " ns is not after the previous scan's " + std::to_string(last_stamp));
            continue;
        }
        const auto t_start = std::chrono::steady_clock::now();
        // 1. Doppler: ego-velocity (mask + Doppler prior).
        odometry::EgoVelocityResult ego;
        if (use_mask || wants_doppler) ego = estimator.Estimate(scan);
        const double doppler_ms = MsSince(t_start);
        mapping::PointMask mask;
        const bool masked = use_mask && ego.valid;
        if (use_mask && !ego.valid) ++unmasked;
        if (masked) {
            mask.resize(scan.size());
            for (Eigen::Index i = 0; i < scan.size(); ++i)
                mask(i) = ego.labels[i] == odometry::PointLabel::kStatic;
        }
        // 2. The prior.
        const double dt = first ? 0.1 : NanosToSeconds(scan.stamp_ns - last_stamp);
        mapping::MotionPrior prior;
        prior.covariance = Matrix6d::Identity() * 1e-6;  // the first scan defines the world
        std::string prior_used = "first scan";
        if (!first) {
            const Eigen::Isometry3d &T_last = trajectory.poses().back().T_world_body;
            const bool has_two = trajectory.size() >= 2 && last_dt > 0.0;
            const Eigen::Isometry3d T_prev2 =
                has_two ? trajectory.poses()[trajectory.size() - 2].T_world_body : T_last;
            auto constvel = [&] {
                return has_two ? mapping::PriorConstantVelocity(T_prev2, T_last, last_dt, dt,
                                                                config.prior)
                               : mapping::PriorFromPreviousPose(T_last, config.prior);
            };
            std::optional<mapping::MotionPrior> built;
            if (opt.prior == "none") built = mapping::PriorFromPreviousPose(T_last, config.prior);
            if (opt.prior == "constvel") built = constvel();
            if (opt.prior == "imu") {
                const Eigen::Vector3d v_world =
                    has_two
                        ? Eigen::Vector3d((T_last.translation() - T_prev2.translation()) / last_dt)
                        : Eigen::Vector3d::Zero();
                built = mapping::PriorFromImu(T_last, v_world, imu, last_stamp, scan.stamp_ns,
                                              dataset.extrinsics.T_base_imu, config.prior);
            }
            if (wants_doppler && ego.valid) {
                const odometry::VehicleMotion motion =
                    kinematics->Motion(ego.v_radar_mps, ego.cov_v_radar);
                if (opt.prior == "doppler")
                    built = mapping::PriorFromDoppler(
                        T_last, TwistOf(kinematics->PlausibleTwist(motion)), dt, config.prior);
                if (opt.prior == "imu+doppler") {
                    // The gyro gives omega and v_base = v_s - omega x s: no model error.
                    mapping::BaseTwist twist = TwistOf(motion);
                    const Eigen::Vector3d gyro_base =
                        dataset.extrinsics.T_base_imu.linear() *
                        MeanAngularVelocity(imu, last_stamp + 1, scan.stamp_ns);
                    if (gyro_base.allFinite())
                        twist.v_base_mps = kinematics->BaseVelocity(ego.v_radar_mps, gyro_base);
                    built = mapping::PriorFromImuAndDoppler(
                        T_last, twist, imu, last_stamp + 1, scan.stamp_ns,
                        dataset.extrinsics.T_base_imu, dt, config.prior);
                }
            }
            prior_used = opt.prior;
            if (!built) {  // no IMU sample / no valid Doppler velocity for this scan
                prior_substitutions[ego.valid || !wants_doppler
                                        ? "no imu samples"
                                        : "doppler: " +
                                              ego.reason.substr(0, ego.reason.find(':'))]++;
                built = constvel();
                prior_used = "constvel";
            }
            prior = *built;
        }
        // 3-5. Registration, refinement, map update.
        const mapping::RegistrationResult r =
            mapper.Register(scan, prior, dt, masked ? &mask : nullptr);
        const double total = MsSince(t_start);
        total_ms.push_back(total);
        if (r.fallback)
            fallback_reasons[r.fallback_reason.substr(0, r.fallback_reason.find(" ("))]++;
        if (scan.empty()) {
            skips.WarnNoFinitePoints(event.scan_index, event.removed_nonfinite_points,
                                     ": pose from the " + prior_used + " prior");
        }
        if (!first && gaps.IsGap(dt)) {
            skips.Warn(event.scan_index, "gap",
                       gaps.Describe(dt) + "; the " + prior_used + " prior spans it");
        }
        nonfinite_points += event.removed_nonfinite_points;
        trajectory.Append(scan.stamp_ns, r.T_world_base);
        positions.push_back(r.T_world_base.translation());
        // The output map: the same points the mapper used (static, in range), finer voxels.
        Eigen::Matrix3Xd p_world(3, scan.size());
        Eigen::Index n = 0;
        const Eigen::Isometry3d T_world_radar = r.T_world_base * dataset.extrinsics.T_base_radar;
        for (Eigen::Index i = 0; i < scan.size(); ++i) {
            const double range = scan.xyz_radar.col(i).norm();
            if (masked && !mask(i)) continue;
            if (range < config.mapper.min_range_m || range > config.mapper.max_range_m) continue;
            p_world.col(n++) = T_world_radar * scan.xyz_radar.col(i);
        }
        output_map.Update(p_world.leftCols(n), r.T_world_base.translation());
        char row[512];
        std::snprintf(row, sizeof(row), "%.9f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%d,%.5f,%d,",
                      NanosToSeconds(scan.stamp_ns), doppler_ms, r.times.preprocess_ms,
                      r.times.registration_ms, r.times.refinement_ms, r.times.map_update_ms, total,
                      r.correspondences, r.fitness_rms_m, r.fallback ? 1 : 0);
        csv << row << Quoted(r.fallback_reason) << '\n';
        ++registered;
        last_dt = first ? 0.0 : dt;
        last_stamp = scan.stamp_ns;
        // IMU samples before this scan are no longer needed.
        imu.erase(std::remove_if(imu.begin(), imu.end(),
                                 [&](const ImuSample &s) { return s.stamp_ns < last_stamp; }),
                  imu.end());
    }
    progress.Finish();
    guard.ThrowIfNoScanUsed(registered, reader->source());

    io::WriteTum(opt.out + "/trajectory.tum", trajectory);
    const Eigen::Matrix3Xd map_points = output_map.Points();
    WritePcd(opt.out + "/map.pcd", map_points);
    WritePly(opt.out + "/map.ply", map_points);
    WriteBirdsEyeImage(opt.out + "/map.png", map_points, positions);
    io::WriteFileAtomically(opt.out + "/scans.csv", [&](std::ostream &os) { os << csv.str(); });
    std::vector<double> sorted = total_ms;
    std::sort(sorted.begin(), sorted.end());
    double mean = 0.0;
    for (double t : sorted) mean += t / sorted.size();
    nlohmann::json summary = {
        {"dataset", dataset.name},
        {"prior", opt.prior},
        {"mask", use_mask},
        {"refinement", config.mapper.refinement == mapping::Refinement::kCeres ? "ceres" : "none"},
        {"method", mapping::ToString(config.mapper.method)},
        {"stopped_early",
         guard.stopped().empty() ? nlohmann::json() : nlohmann::json(guard.stopped())},
        {"scans", scans},
        {"scans_registered", registered},
        {"scans_skipped", scans - registered},
        {"skip_reasons", skips.Counts()},
        {"skipped", skips.Scans()},
        {"warnings", skips.WarningCounts()},
        {"warned", skips.Warnings()},
        {"nonfinite_points_removed", nonfinite_points},
        {"fallbacks", mapper.fallbacks()},
        {"fallback_reasons", fallback_reasons},
        {"prior_substitutions_constvel", prior_substitutions},
        {"scans_without_mask", unmasked},
        {"time_per_scan_ms",
         {{"mean", mean},
          {"median", sorted[sorted.size() / 2]},
          {"p95", sorted[static_cast<std::size_t>(0.95 * (sorted.size() - 1))]}}},
        {"map_points", map_points.cols()},
        {"path_length_m", trajectory.PathLength()}};
    io::WriteFileAtomically(opt.out + "/summary.json",
                            [&](std::ostream &os) { os << summary.dump(2) << '\n'; });
    std::fprintf(stderr,
                 "map: %zu scans, %zu registered, %d fell back to the prior, %.2f ms/scan, path "
                 "%.1f m -> %s\n",
                 scans, registered, mapper.fallbacks(), mean, trajectory.PathLength(),
                 opt.out.c_str());
    guard.ThrowIfStopped("map", scans, opt.out);
}

}  // namespace

void RegisterMapCommand(CLI::App &app) {
    auto opt = std::make_shared<MapOptions>();
    auto *cmd = app.add_subcommand("map",
                                   "Radar scan-to-map mapping with a motion prior, the Doppler "
                                   "dynamic-point mask and a Doppler-aware Ceres refinement.");
    cmd->add_option("DATASET", opt->dataset, "dataset description (.yaml) or .bag")->required();
    cmd->add_option("--out", opt->out, "output folder")->required();
    cmd->add_option("--prior", opt->prior, "motion prior (default doppler)")
        ->check(CLI::IsMember({"none", "constvel", "imu", "doppler", "imu+doppler"}));
    cmd->add_option("--config", opt->config, "mapper settings (see configs/mapper.yaml)");
    cmd->add_option("--odometry-config", opt->odometry_config,
                    "Doppler estimator settings (see configs/odometry.yaml)");
    cmd->add_flag("--no-mask", opt->no_mask, "keep the dynamic points (ablation)");
    cmd->add_option("--refine", opt->refine, "ceres (default) or none (PCL registration only)")
        ->check(CLI::IsMember({"ceres", "none"}));
    cmd->callback([opt] { RunMap(*opt); });
}

}  // namespace dorado::apps
