// `dorado odometry DATASET --out DIR`: the paper's Doppler-only odometry over a whole dataset.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.hpp"
#include "dorado/core/time.hpp"
#include "dorado/io/atomic_file.hpp"
#include "dorado/io/dataset.hpp"
#include "dorado/io/trajectory_io.hpp"
#include "dorado/odometry/doppler_odometry.hpp"
#include "odometry_config.hpp"
#include "progress.hpp"
#include "skip_log.hpp"
#include "stream_guard.hpp"

namespace dorado::apps {
namespace {

struct OdometryOptions {
    std::string dataset, out, config, rotation;
    bool masks = false;
};

/// Mean gyro rate of the IMU samples in (t0, t1], rotated into the base frame; NaN when none.
class GyroWindow {
  public:
    explicit GyroWindow(const Eigen::Matrix3d &R_base_imu) : R_base_imu_(R_base_imu) {}
    void Add(const ImuSample &s) {
        if (s.omega_imu_radps.allFinite()) samples_.push_back(s);
    }
    Eigen::Vector3d MeanInBase(int64_t t0_ns, int64_t t1_ns) {
        const Eigen::Vector3d mean = MeanAngularVelocity(samples_, t0_ns + 1, t1_ns);
        // Samples up to t1 are used: drop them, keep later ones for the next interval.
        samples_.erase(std::remove_if(samples_.begin(), samples_.end(),
                                      [&](const ImuSample &s) { return s.stamp_ns <= t1_ns; }),
                       samples_.end());
        return R_base_imu_ * mean;  // NaN stays NaN
    }

  private:
    Eigen::Matrix3d R_base_imu_;
    std::vector<ImuSample> samples_;
};

std::string Num(double v) {
    if (!std::isfinite(v)) return "nan";
    std::ostringstream s;
    s << std::setprecision(9) << v;
    return s.str();
}

std::string CsvText(std::string text) {  // quoted, with inner quotes doubled
    std::string out = "\"";
    for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
    return out + "\"";
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
    "cov_omega_model_xz,cov_omega_model_yy,cov_omega_model_yz,cov_omega_model_zz\n";

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
    const std::string reason =
        step.used_fallback ? step.fallback_reason : (e.valid ? "" : e.reason);
    row << ',' << e.inliers << ',' << points << ',' << (e.valid ? 1 : 0) << ',' << CsvText(reason);
    for (int k = 0; k < 3; ++k) row << ',' << Num(gyro_base[k]);
    row << ',' << Num(time_ms);
    // The kinematic model's own error (vehicle.model_noise): add it to cov_omega for the total.
    AppendCovariance(row, step.motion.cov_model.bottomRightCorner<3, 3>());
    row << '\n';
    return row.str();
}

void WriteMask(const std::string &path, const odometry::OdometryStep &step) {
    io::WriteFileAtomically(path, [&](std::ostream &os) {
        os << "# stamp_ns " << step.stamp_ns << ", one label per point in input order: "
           << "0 static, 1 dynamic, 2 filtered\n";
        for (const auto label : step.ego.labels) os << static_cast<int>(label) << '\n';
    });
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

void RunOdometry(const OdometryOptions &opt) {
    const io::DatasetConfig dataset = io::ResolveDataset(opt.dataset);
    odometry::DopplerOdometryConfig config;
    if (!opt.config.empty()) config = LoadOdometryConfig(opt.config);
    if (!opt.rotation.empty()) config.rotation = ParseRotationSource(opt.rotation, "--rotation");
    const bool needs_imu = config.rotation != odometry::RotationSource::kDoppler;
    const bool has_imu =
        dataset.reader == io::ReaderKind::kRosbag && !dataset.rosbag.imu_topic.empty();
    if (needs_imu && !has_imu) {
        const std::string file = dataset.config_path.empty() ? opt.dataset : dataset.config_path;
        throw io::ConfigError(file +
                              ": key 'rosbag.imu_topic': rotation from the IMU needs an "
                              "IMU topic in the dataset description");
    }
    odometry::DopplerOdometry odometry(config, dataset.extrinsics, dataset.vehicle);
    io::MakeDirectories(opt.out);
    if (opt.masks) io::MakeDirectories(opt.out + "/masks");

    const std::size_t expected = CountRadarMessages(dataset, needs_imu, "rotation from the IMU");
    auto reader = io::OpenDataset(dataset);
    Progress progress("odometry", expected);
    GyroWindow gyro(dataset.extrinsics.T_base_imu.linear());
    std::string csv = kCsvHeader;
    std::vector<double> times_ms, inlier_ratios;
    std::map<std::string, int> invalid_reasons;
    SkipLog skips;
    GapWatch gaps;
    std::size_t scans = 0, used = 0, fallbacks = 0;
    Eigen::Index nonfinite_points = 0;
    int64_t last_stamp = 0;
    bool has_last = false;
    io::DatasetEvent event;
    StreamGuard guard;  // Ctrl-C or a reader error mid-stream: stop, write what was done
    while (guard.Next(*reader, event)) {
        if (event.kind == io::DatasetEvent::Kind::kImu) gyro.Add(event.imu);
        if (event.kind == io::DatasetEvent::Kind::kBadScan) {
            ++scans;
            skips.Add(event.scan_index, "unreadable scan", event.problem);
        }
        if (event.kind != io::DatasetEvent::Kind::kRadarScan) continue;
        ++scans;
        const Eigen::Vector3d gyro_base =
            has_last ? gyro.MeanInBase(last_stamp, event.stamp_ns) : Eigen::Vector3d::Constant(NAN);
        const auto start = std::chrono::steady_clock::now();
        const auto step = odometry.Register(event.scan, gyro_base);
        const double ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count();
        progress.Update(scans);
        if (!step.integrated) {
            skips.Add(event.scan_index, "timestamp out of order", step.skip_reason);
            continue;
        }
        if (event.scan.empty()) {
            skips.WarnNoFinitePoints(
                event.scan_index, event.removed_nonfinite_points,
                step.used_fallback ? ": " + step.fallback_reason : std::string());
        }
        if (has_last && gaps.IsGap(step.dt_s)) {
            skips.Warn(event.scan_index, "gap",
                       gaps.Describe(step.dt_s) + "; integrated this scan's twist over it");
        }
        nonfinite_points += event.removed_nonfinite_points;
        has_last = true;
        last_stamp = event.stamp_ns;
        ++used;
        fallbacks += step.used_fallback;
        times_ms.push_back(ms);
        if (!step.ego.valid && config.rotation != odometry::RotationSource::kImuOnly) {
            invalid_reasons[step.ego.reason.substr(0, step.ego.reason.find(':'))]++;
        } else if (step.ego.points_used > 0) {
            inlier_ratios.push_back(static_cast<double>(step.ego.inliers) / step.ego.points_used);
        }
        csv += CsvRow(step, event.scan.size(), gyro_base, ms);
        if (opt.masks) {
            char name[32];
            std::snprintf(name, sizeof(name), "/masks/%06zu.txt", event.scan_index);
            WriteMask(opt.out + name, step);
        }
    }
    progress.Finish();
    guard.ThrowIfNoScanUsed(used, reader->source());

    io::WriteTum(opt.out + "/trajectory.tum", odometry.trajectory());
    io::WriteFileAtomically(opt.out + "/velocities.csv", [&](std::ostream &os) { os << csv; });
    const char *rotation_names[] = {"doppler", "imu", "imu-only"};
    nlohmann::json summary = {
        {"dataset", dataset.name},
        {"rotation", rotation_names[static_cast<int>(config.rotation)]},
        {"stopped_early",
         guard.stopped().empty() ? nlohmann::json() : nlohmann::json(guard.stopped())},
        {"scans", scans},
        {"scans_used", used},
        {"scans_skipped", scans - used},
        {"skip_reasons", skips.Counts()},
        {"skipped", skips.Scans()},
        {"warnings", skips.WarningCounts()},
        {"warned", skips.Warnings()},
        {"nonfinite_points_removed", nonfinite_points},
        {"scans_with_fallback_twist", fallbacks},
        {"invalid_velocity_reasons", invalid_reasons},
        {"inlier_ratio", Stats(inlier_ratios)},
        {"time_per_scan_ms", Stats(times_ms)},
        {"path_length_m", odometry.trajectory().PathLength()}};
    io::WriteFileAtomically(opt.out + "/summary.json",
                            [&](std::ostream &os) { os << summary.dump(2) << '\n'; });
    std::fprintf(stderr,
                 "odometry: %zu scans, %zu used, %zu with a fallback twist, %.3f ms/scan, "
                 "path %.1f m -> %s\n",
                 scans, used, fallbacks,
                 times_ms.empty() ? 0.0 : summary["time_per_scan_ms"]["mean"].get<double>(),
                 odometry.trajectory().PathLength(), opt.out.c_str());
    guard.ThrowIfStopped("odometry", scans, opt.out);
}

}  // namespace

void RegisterOdometryCommand(CLI::App &app) {
    auto opt = std::make_shared<OdometryOptions>();
    auto *cmd = app.add_subcommand("odometry",
                                   "Doppler-only single-scan odometry (Galeote-Luque et al.): "
                                   "radar velocity per scan, vehicle "
                                   "twist from the kinematic model, integrated on SE(3).");
    cmd->add_option("DATASET", opt->dataset, "dataset description (.yaml) or .bag")->required();
    cmd->add_option("--out", opt->out, "output folder")->required();
    cmd->add_option("--config", opt->config, "odometry settings (see configs/odometry.yaml)");
    cmd->add_option("--rotation", opt->rotation,
                    "doppler (kinematic model), imu (gyro rotation + Doppler translation) or "
                    "imu-only (gyro rotation, no translation)")
        ->check(CLI::IsMember({"doppler", "imu", "imu-only"}));
    cmd->add_flag("--masks", opt->masks,
                  "write DIR/masks/NNNNNN.txt: per-point static/dynamic labels");
    cmd->callback([opt] { RunOdometry(*opt); });
}

}  // namespace dorado::apps
