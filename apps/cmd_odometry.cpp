// `dorado odometry DATASET --out DIR`: the paper's Doppler-only odometry over a whole dataset.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.hpp"
#include "dorado/config/odometry_config.hpp"
#include "dorado/core/angles.hpp"
#include "dorado/core/time.hpp"
#include "dorado/frontend/radar_front_end.hpp"
#include "dorado/io/atomic_file.hpp"
#include "dorado/io/csv_text.hpp"
#include "dorado/io/dataset.hpp"
#include "dorado/io/trajectory_io.hpp"
#include "output_folder.hpp"
#include "plausibility.hpp"
#include "preflight.hpp"
#include "progress.hpp"
#include "scan_loop.hpp"
#include "stream_guard.hpp"

namespace dorado::apps {
namespace {

struct OdometryOptions {
    std::string dataset, data, out, config, method, rotation, radars;
    bool masks = false, accept_implausible = false;
    io::DatasetChoice choice;  // --scene, --sequence
};

std::string Num(double v) {
    if (!std::isfinite(v)) return "nan";
    std::ostringstream s;
    s << std::setprecision(9) << v;
    return s.str();
}

void AppendCovariance(std::ostream &row, const Eigen::Matrix3d &C) {
    row << ',' << Num(C(0, 0)) << ',' << Num(C(0, 1)) << ',' << Num(C(0, 2)) << ',' << Num(C(1, 1))
        << ',' << Num(C(1, 2)) << ',' << Num(C(2, 2));
}

constexpr const char *kCsvHeader =
    "t,v_radar_x,v_radar_y,v_radar_z,cov_v_xx,cov_v_xy,cov_v_xz,cov_v_yy,cov_v_yz,cov_v_zz,"
    "omega_base_x,omega_base_y,omega_base_z,cov_omega_xx,cov_omega_xy,cov_omega_xz,cov_omega_yy,"
    "cov_omega_yz,cov_omega_zz,v_base_x,v_base_y,v_base_z,inliers,points,valid,reason,"
    "gyro_base_x,gyro_base_y,gyro_base_z,time_ms,cov_omega_model_xx,cov_omega_model_xy,"
    "cov_omega_model_xz,cov_omega_model_yy,cov_omega_model_yz,cov_omega_model_zz,fallback_cause,"
    "zero_velocity_update,"
    "ground_valid,ground_reason,ground_roll_deg,ground_pitch_deg,ground_inliers,"
    "ground_correction_roll_deg,ground_correction_pitch_deg,ground_residual_m,ground_chi2,"
    "velocity_prediction\n";

// The ground-plane attitude columns (ground.enabled; the reason names a scan without ground).
void AppendGround(std::ostream &row, const odometry::GroundAttitudeStep &g) {
    const odometry::GroundObservation &o = g.observation;
    row << ',' << (o.valid ? 1 : 0) << ',' << odometry::ToString(o.fallback) << ','
        << Num(RadToDeg(o.roll_pitch_rad.x())) << ',' << Num(RadToDeg(o.roll_pitch_rad.y())) << ','
        << o.inliers << ',' << Num(RadToDeg(g.correction_rad.x())) << ','
        << Num(RadToDeg(g.correction_rad.y())) << ',' << Num(o.residual_sigma_m) << ','
        << Num(g.innovation_chi2);
}

std::string CsvRow(const odometry::OdometryStep &step, Eigen::Index points,
                   const Eigen::Vector3d &gyro_base, double time_ms) {
    std::ostringstream row;
    const auto &e = step.ego;
    char stamp[32];
    std::snprintf(stamp, sizeof(stamp), "%.9f", NanosToSeconds(step.stamp_ns));
    row << stamp;
    for (int k = 0; k < 3; ++k) row << ',' << Num(e.v_radar_mps[k]);
    AppendCovariance(row, e.cov_v_radar);
    for (int k = 0; k < 3; ++k) row << ',' << Num(step.omega_base_used_radps[k]);
    AppendCovariance(row, step.motion.cov_omega_base);
    for (int k = 0; k < 3; ++k) row << ',' << Num(step.v_base_used_mps[k]);
    // The fallback reason starts with the estimator's reason when the scan was invalid.
    const std::string reason = step.used_fallback ? step.fallback_reason : odometry::Describe(e);
    row << ',' << e.inliers << ',' << points << ',' << (e.valid() ? 1 : 0) << ','
        << io::CsvQuoted(reason);
    for (int k = 0; k < 3; ++k) row << ',' << Num(gyro_base[k]);
    row << ',' << Num(time_ms);
    // The kinematic model's own error (vehicle.model_noise): add it to cov_omega for the total.
    AppendCovariance(row, step.motion.cov_model.bottomRightCorner<3, 3>());
    // Every fallback or substitution has one cause (none for the scan's own twist).
    row << ',' << odometry::ToString(step.fallback_cause) << ','
        << (step.zero_velocity_update ? 1 : 0);
    AppendGround(row, step.ground);
    // odometry.max_acceleration_mps2: was RANSAC held near the previous velocity (none when off).
    row << ',' << odometry::ToString(e.prediction) << '\n';
    return row.str();
}

void WriteMask(const std::string &out_dir, std::size_t scan_index,
               const odometry::OdometryStep &step) {
    std::vector<int> labels;
    labels.reserve(step.ego.labels.size());
    for (const auto label : step.ego.labels) labels.push_back(static_cast<int>(label));
    WriteMaskFile(out_dir, scan_index, step.stamp_ns, "0 static, 1 dynamic, 2 filtered", labels);
}

nlohmann::json Stats(std::vector<double> v) {
    if (v.empty()) return nullptr;
    std::sort(v.begin(), v.end());
    double sum = 0.0;
    for (double x : v) sum += x;
    const auto at = [&](double q) { return v[static_cast<std::size_t>(q * (v.size() - 1))]; };
    return {{"mean", sum / v.size()}, {"median", at(0.5)}, {"p05", at(0.05)},
            {"p95", at(0.95)},        {"min", v.front()},  {"max", v.back()}};
}

// " (invalid_velocity 1, no_imu_samples 3)", or "" without fallbacks.
std::string CauseList(const std::map<odometry::FallbackCause, int> &causes) {
    std::string text;
    for (const auto &[cause, count] : causes)
        text += (text.empty() ? " (" : ", ") + std::string(odometry::ToString(cause)) + ' ' +
                std::to_string(count);
    return text.empty() ? text : text + ")";
}

void RunOdometry(const OdometryOptions &opt) {
    const io::DatasetConfig dataset =
        SelectRadar(io::ResolveDataset(opt.dataset, opt.data, opt.choice), opt.radars);
    const nlohmann::json radars_used = ReportRadarsUsed(dataset, opt.dataset, "odometry");
    StateAssumptions(dataset, opt.dataset, "odometry");
    frontend::FrontEndConfig config;
    config.run_mapper = false;
    if (!opt.config.empty()) config.odometry = dorado::config::LoadOdometryConfig(opt.config);
    if (!opt.rotation.empty())
        throw io::ConfigError(
            "--rotation is now --method (doppler | imu | imu+doppler; the old "
            "'imu' is 'imu+doppler', 'imu-only' is 'imu')");
    if (!opt.method.empty())
        config.odometry.method = dorado::config::ParseOdometryMethodKey(opt.method, "--method");
    const odometry::OdometryMethod method = config.odometry.method;
    const bool needs_imu = odometry::NeedsImu(method);
    if (needs_imu && !HasImu(dataset)) {
        throw io::ConfigError(DatasetFile(dataset, opt.dataset) + ": key '" + ImuKey(dataset) +
                              "': rotation from the IMU needs an IMU in the dataset description");
    }
    config.odometry.ego_velocity.sensor = dataset.radar;  // the radar: noise, ambiguity
    frontend::RadarFrontEnd front_end(config, dataset.extrinsics, dataset.vehicle);
    const std::size_t expected = CountRadarMessages(dataset, needs_imu, "rotation from the IMU");
    CheckBeforeWork(dataset, opt.out);
    PrepareOutputFolder(opt.out);
    if (opt.masks) io::MakeDirectories(opt.out + "/masks");

    auto reader = io::OpenDataset(dataset);
    Progress progress("odometry", expected);
    std::string csv = kCsvHeader;
    std::vector<double> times_ms, inlier_ratios;
    std::map<odometry::FallbackCause, int> fallback_causes;
    std::map<odometry::PredictionUse, int> predictions;
    std::map<odometry::EgoVelocityFailure, int> invalid_reasons;
    std::map<odometry::EgoVelocityFailure, std::string> first_invalid;  // each's first, once
    std::size_t fallbacks = 0, zero_velocity_updates = 0;
    std::size_t ground_scans = 0, ground_relevels = 0;
    std::map<odometry::GroundFallback, int> ground_fallbacks;
    PlausibilityWatch plausibility(dataset.radar.doppler_unambiguous_mps);
    ScanLoop loop(front_end);
    StreamGuard guard;  // Ctrl-C or a reader error mid-stream: stop, write what was done
    loop.Run(
        *reader, guard, progress,
        [&](const io::DatasetEvent &event, const frontend::FrontEndResult &result) {
            const odometry::OdometryStep &step = result.odometry;
            plausibility.AddPoints(event.scan);
            plausibility.AddSpeed(event.stamp_ns, step.ego.valid(), step.ego.v_radar_mps.norm());
            fallbacks += step.used_fallback;
            zero_velocity_updates += step.zero_velocity_update;
            if (step.used_fallback) fallback_causes[step.fallback_cause]++;
            predictions[step.ego.prediction]++;
            if (config.odometry.ground.enabled && step.integrated) {
                const auto &ground = step.ground.observation;
                ground_scans += ground.valid;
                ground_relevels += step.ground.relevelled;
                if (!ground.valid) ground_fallbacks[ground.fallback]++;
            }
            times_ms.push_back(result.times.total_ms);
            if (!step.ego.valid() && method != odometry::OdometryMethod::kImu) {
                if (invalid_reasons[step.ego.failure]++ == 0)
                    first_invalid[step.ego.failure] = "scan " + std::to_string(event.scan_index) +
                                                      ": " + odometry::Describe(step.ego);
            } else if (step.ego.points_used > 0) {
                inlier_ratios.push_back(static_cast<double>(step.ego.inliers) /
                                        step.ego.points_used);
            }
            csv += CsvRow(step, event.scan.size(), result.gyro_base_radps, result.times.total_ms);
            if (opt.masks) WriteMask(opt.out, event.scan_index, step);
        });
    guard.ThrowIfNoScanUsed(loop.used(), reader->source());

    io::WriteTum(opt.out + "/trajectory.tum", front_end.trajectory());
    io::WriteFileAtomically(opt.out + "/velocities.csv", [&](std::ostream &os) { os << csv; });
    nlohmann::json summary = {
        {"dataset", dataset.name},
        {"method", odometry::ToString(method)},
        {"stopped_early",
         guard.stopped().empty() ? nlohmann::json() : nlohmann::json(guard.stopped())},
        {"scans", loop.scans()},
        {"scans_used", loop.used()},
        {"scans_skipped", loop.scans() - loop.used()},
        {"scans_with_fallback_twist", fallbacks},
        // by cause (odometry::FallbackCause): they add up to scans_with_fallback_twist
        {"fallback_causes", CountsByKey(fallback_causes)},
        {"scans_zero_velocity_update", zero_velocity_updates},
        // odometry.max_acceleration_mps2: scans by what the held RANSAC did (none: not held)
        {"velocity_prediction", CountsByKey(predictions)},
        {"invalid_velocity_reasons", CountsByKey(invalid_reasons)},
        {"inlier_ratio", Stats(inlier_ratios)},
        {"time_per_scan_ms", Stats(times_ms)},
        {"path_length_m", front_end.trajectory().PathLength()}};
    if (!radars_used.is_null()) summary["radars"] = radars_used;
    if (config.odometry.ground.enabled) {
        summary["ground"] = {{"scans_with_ground", ground_scans},
                             {"relevelled", ground_relevels},
                             {"scans_without_ground", CountsByKey(ground_fallbacks)}};
    }
    AddStreamCounts(loop, summary);
    const std::vector<std::string> implausible = plausibility.Problems(
        loop.used(), fallbacks, "used a fallback twist",
        method == odometry::OdometryMethod::kImu ? -1.0 : front_end.trajectory().PathLength());
    summary.update(PlausibilityRecord(implausible, plausibility, opt.accept_implausible));
    WriteSummary(opt.out, summary);
    std::fprintf(stderr,
                 "odometry: %zu scans, %zu used, %zu with a fallback twist%s, %.3f ms/scan, "
                 "path %.1f m -> %s\n",
                 loop.scans(), loop.used(), fallbacks, CauseList(fallback_causes).c_str(),
                 times_ms.empty() ? 0.0 : summary["time_per_scan_ms"]["mean"].get<double>(),
                 front_end.trajectory().PathLength(), opt.out.c_str());
    for (const auto &[failure, count] : invalid_reasons)  // each cause once, not once per scan
        std::fprintf(stderr, "odometry: no valid velocity on %d scans (%s); the first, %s\n", count,
                     odometry::ToString(failure), first_invalid[failure].c_str());
    guard.ThrowIfStopped("odometry", loop.scans(), opt.out);
    EndIfImplausible(implausible, "odometry", opt.out, opt.accept_implausible);
}

}  // namespace

void RegisterOdometryCommand(CLI::App &app) {
    auto opt = std::make_shared<OdometryOptions>();
    auto *cmd = app.add_subcommand("odometry",
                                   "Doppler-only single-scan odometry (Galeote-Luque et al.): "
                                   "radar velocity per scan, vehicle "
                                   "twist from the kinematic model, integrated on SE(3).");
    cmd->add_option(
           "DATASET", opt->dataset,
           "dataset description (.yaml), or a recording (.bag, .db3, .mcap, rosbag2 folder)")
        ->required();
    AddDataOption(cmd, opt->data);
    cmd->add_option("--out", opt->out, "output folder")->required();
    AddDatasetChoiceOptions(*cmd, opt->choice);
    cmd->add_option("--config", opt->config,
                    "odometry settings (configs/odometry.yaml; every key and default: "
                    "`dorado config print odometry`)");
    cmd->add_option("--method", opt->method,
                    "doppler (kinematic model, default), imu (gyro rotation, no translation) or "
                    "imu+doppler (gyro rotation + Doppler translation)");
    cmd->add_option("--rotation", opt->rotation, "replaced by --method")->group("");
    cmd->add_option("--radars", opt->radars,
                    "with the dataset's radars: list: first (default: the folder: + extrinsics: "
                    "radar) or a radar's name; every radar's twist: dorado twist");
    cmd->add_flag("--masks", opt->masks,
                  "write DIR/masks/NNNNNN.txt: per-point static/dynamic labels");
    AddAcceptImplausibleFlag(cmd, opt->accept_implausible);
    cmd->callback([opt] { RunOdometry(*opt); });
}

}  // namespace dorado::apps
