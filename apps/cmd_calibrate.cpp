// `dorado calibrate rotation|roll|sx DATASET --out FILE.yaml`: the paper's calibration (IV-A).
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "commands.hpp"
#include "dorado/config/odometry_config.hpp"
#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/core/time.hpp"
#include "dorado/io/atomic_file.hpp"
#include "dorado/io/dataset.hpp"
#include "dorado/odometry/calibration.hpp"
#include "dorado/odometry/ego_velocity.hpp"
#include "dorado/odometry/inertial_check.hpp"
#include "one_of.hpp"
#include "progress.hpp"
#include "scan_loop.hpp"

namespace dorado::apps {
namespace {

struct CalibrateOptions {
    std::string step, dataset, data, out, config;
    double from_s = -1.0, to_s = -1.0;
    double min_speed_mps = 0.2;
    double window_s = 0.5, rest_s = 1.0;  // doppler-sign
    io::DatasetChoice choice;             // --scene, --sequence
    double max_sigma_m = 0.1;             // sx: refused above
    double max_sigma_deg = 0.5;           // rotation, roll: refused above
    bool no_drive_checks = false;
};

/// Per valid, moving scan in the time range: its time, the radar velocity and the mean gyro rate
/// in the base frame over the interval since the previous scan (NaN without IMU); the gyro of the
/// scans at rest (slower than --min-speed) for its bias.
struct Samples {
    std::vector<double> t_s;
    std::vector<Eigen::Vector3d> v_radar, gyro_base, gyro_at_rest;
    std::size_t scans = 0, rejected = 0, imu_samples = 0;
    double drive_s = 0.0;  ///< the last scan's time after the first
};

Samples Collect(const CalibrateOptions &opt, const io::DatasetConfig &dataset) {
    odometry::EgoVelocityConfig ego;
    if (!opt.config.empty()) ego = dorado::config::LoadOdometryConfig(opt.config).ego_velocity;
    ego.sensor = dataset.radar;  // its direction noise and Doppler ambiguity, as the odometry's
    odometry::EgoVelocityEstimator estimator(ego);
    auto reader = io::OpenDataset(dataset);
    Progress progress("calibrate " + opt.step, 0);
    const Eigen::Matrix3d R_base_imu = dataset.extrinsics.T_base_imu.linear();
    ImuWindow imu;
    Samples out;
    bool has_first = false, has_last = false;
    int64_t first_ns = 0, last_ns = 0;
    io::DatasetEvent event;
    while (reader->Next(event)) {
        if (event.kind == io::DatasetEvent::Kind::kImu) {
            imu.Add(event.imu);
            ++out.imu_samples;
        }
        if (event.kind != io::DatasetEvent::Kind::kRadarScan) continue;
        if (!has_first) first_ns = event.stamp_ns, has_first = true;
        progress.Update(++out.scans);
        const double t = NanosToSeconds(event.stamp_ns - first_ns);
        const Eigen::Vector3d gyro =
            has_last ? Eigen::Vector3d(R_base_imu * imu.MeanGyro(last_ns, event.stamp_ns))
                     : Eigen::Vector3d::Constant(NAN);
        imu.DropUpTo(event.stamp_ns);
        has_last = true;
        last_ns = event.stamp_ns;
        out.drive_s = t;
        if ((opt.from_s >= 0 && t < opt.from_s) || (opt.to_s >= 0 && t > opt.to_s)) continue;
        const auto r = estimator.Estimate(event.scan);
        if (!r.valid() || r.v_radar_mps.norm() < opt.min_speed_mps) {
            ++out.rejected;
            if (r.valid() && gyro.allFinite()) out.gyro_at_rest.push_back(gyro);
            continue;
        }
        out.t_s.push_back(t);
        out.v_radar.push_back(r.v_radar_mps);
        out.gyro_base.push_back(gyro);
    }
    progress.Finish();
    return out;
}

/// Refuses a --from/--to window that is not inside the drive (the time of its last scan).
void CheckWindow(const CalibrateOptions &opt, const Samples &samples) {
    const auto past = [&](const char *flag, double value) {
        char text[200];
        std::snprintf(text, sizeof(text),
                      "%s %g s is past the drive's end: its last scan is %.1f s after the first",
                      flag, value, samples.drive_s);
        return std::string(text);
    };
    if (opt.from_s >= 0 && opt.from_s >= samples.drive_s)
        throw io::DatasetError(opt.dataset + ": " + past("--from", opt.from_s));
    if (opt.to_s >= 0 && opt.to_s > samples.drive_s + 0.5)
        throw io::DatasetError(opt.dataset + ": " + past("--to", opt.to_s) +
                               " (give a window inside it, or no --to)");
    if (opt.from_s >= 0 && opt.to_s >= 0 && opt.to_s <= opt.from_s)
        throw io::DatasetError(opt.dataset + ": --to must be after --from");
}

/// Scans over six seconds: the lag over which their errors are taken as correlated (tyre slip and
/// the instant centre of rotation wander over seconds, not scans).
int CorrelationLag(const Samples &samples) {
    constexpr double kCorrelationS = 6.0;
    if (samples.t_s.size() < 2) return 0;
    const double span = samples.t_s.back() - samples.t_s.front();
    const double rate = span > 0.0 ? (samples.t_s.size() - 1) / span : 0.0;
    return std::max(1, static_cast<int>(std::lround(kCorrelationS * rate)));
}

std::string Fixed(double value, int digits) {
    char text[64];
    std::snprintf(text, sizeof(text), "%.*f", digits, value);
    return text;
}

/// A refusal: the drive does not hold what the step needs (or --no-drive-checks was given).
void Refuse(const CalibrateOptions &opt, const std::string &why) {
    if (opt.no_drive_checks) {
        std::fprintf(stderr, "calibrate %s: warning: %s (--no-drive-checks: written anyway)\n",
                     opt.step.c_str(), why.c_str());
        return;
    }
    throw io::DatasetError(opt.dataset + ": calibrate " + opt.step + " refused: " + why +
                           "; nothing was written (--no-drive-checks writes it anyway)");
}

/// Turning the step needs: the heading change the gyro saw over the used scans [rad].
double TotalTurn(const Samples &samples, const std::vector<double> &yaw_rate) {
    double turn = 0.0;
    for (std::size_t i = 1; i < samples.t_s.size() && i < yaw_rate.size(); ++i) {
        const double dt = samples.t_s[i] - samples.t_s[i - 1];
        if (dt > 0.0 && dt < 1.0) turn += std::abs(yaw_rate[i]) * dt;
    }
    return turn;
}

std::string Vec(const Eigen::Vector3d &v) {
    std::ostringstream s;
    const Eigen::Vector3d w = v.array() + 0.0;  // no "-0"
    s << std::setprecision(8) << '[' << w.x() << ", " << w.y() << ", " << w.z() << ']';
    return s.str();
}

std::string Vec4(double x, double y, double z, double w) {
    std::ostringstream s;
    s << std::setprecision(10) << '[' << x << ", " << y << ", " << z << ", " << w << ']';
    return s.str();
}

// The snippet the dataset description accepts (rotation as roll, pitch, yaw with
// R = Rz(yaw) Ry(pitch) Rx(roll)).
void WriteSnippet(const std::string &path, const std::string &comment, const Eigen::Isometry3d &T) {
    const Eigen::Vector3d rpy = RadToDeg(RollPitchYaw(T.linear()));
    io::WriteFileAtomically(path, [&](std::ostream &os) {
        os << comment << "extrinsics:\n  T_base_radar:\n    translation_m: " << Vec(T.translation())
           << "\n    rotation_rpy_deg: " << Vec(rpy) << "\n";
    });
}

// Every valid ego-velocity (at rest too) with its stamp, and every IMU sample.
void CollectAll(const CalibrateOptions &opt, const io::DatasetConfig &dataset,
                std::vector<odometry::StampedRadarVelocity> &velocities,
                std::vector<ImuSample> &imu, std::size_t &scans) {
    odometry::EgoVelocityConfig ego;
    if (!opt.config.empty()) ego = dorado::config::LoadOdometryConfig(opt.config).ego_velocity;
    ego.sensor = dataset.radar;
    odometry::EgoVelocityEstimator estimator(ego);
    auto reader = io::OpenDataset(dataset);
    Progress progress("calibrate " + opt.step, 0);
    io::DatasetEvent event;
    while (reader->Next(event)) {
        if (event.kind == io::DatasetEvent::Kind::kImu && event.imu.omega_imu_radps.allFinite() &&
            event.imu.accel_imu_mps2.allFinite() &&
            (imu.empty() || event.imu.stamp_ns > imu.back().stamp_ns))
            imu.push_back(event.imu);
        if (event.kind != io::DatasetEvent::Kind::kRadarScan) continue;
        progress.Update(++scans);
        const auto r = estimator.Estimate(event.scan);
        if (r.valid()) velocities.push_back({event.stamp_ns, r.v_radar_mps});
    }
    progress.Finish();
}

// `dorado calibrate doppler-sign`: the ego-velocity fit cannot tell the Doppler sign (negating
// every Doppler negates v with the same residuals); the accelerometer can.
void RunDopplerSign(const CalibrateOptions &opt, const io::DatasetConfig &dataset) {
    std::vector<odometry::StampedRadarVelocity> velocities;
    std::vector<ImuSample> imu;
    std::size_t scans = 0;
    CollectAll(opt, dataset, velocities, imu, scans);
    odometry::InertialCheckConfig config;
    config.window_s = opt.window_s;
    config.rest_s = opt.rest_s;
    config.max_time_offset_s = 0.2;
    odometry::InertialCheck c;
    try {
        c = odometry::CompareWithImu(velocities, imu, dataset.extrinsics, config);
    } catch (const std::invalid_argument &e) {
        throw io::DatasetError(ImuSource(dataset) + ": " + e.what());
    }
    if (c.doppler_sign == 0)
        throw io::DatasetError(ImuSource(dataset) + ": no " + std::to_string(opt.window_s) +
                               " s window with motion where scans and IMU samples overlap (" +
                               std::to_string(velocities.size()) + " valid scans, " +
                               std::to_string(imu.size()) + " IMU samples): check the stamps");
    std::ostringstream text;
    text << std::setprecision(3) << "# dorado calibrate doppler-sign: " << velocities.size()
         << " valid scans of " << scans << ", " << c.as_given.windows << " windows of "
         << opt.window_s << " s with motion\n"
         << "#   velocity change, IMU vs Doppler: sign as given: slope " << c.as_given.slope
         << ", residual RMS " << c.as_given.rms_residual_mps << " m/s; flipped: slope "
         << c.flipped.slope << ", residual RMS " << c.flipped.rms_residual_mps
         << " m/s (signal RMS " << c.as_given.rms_delta_v_mps << " m/s)\n"
         << "#   best scan time offset " << c.best_time_offset_s << " s: slope "
         << c.at_best_offset.slope << ", residual RMS " << c.at_best_offset.rms_residual_mps
         << " m/s (rest window: gyro RMS " << c.rest_gyro_rms_radps << " rad/s)\n";
    const Eigen::Vector3d phi_deg = RadToDeg(c.rotation_correction_base_rad);
    text << "#   extrinsics.T_base_radar rotation correction (base frame, applied on the left): "
         << phi_deg.norm() << " deg (rotation vector " << Vec(phi_deg)
         << " deg), residual RMS then " << c.rms_residual_corrected_mps << " m/s\n";
    if (!(std::abs(c.at_best_offset.slope - 1.0) < 0.3))
        text << "#   WARNING: the slope is far from 1: check extrinsics.T_base_radar's rotation\n";
    std::cerr << text.str();
    const double sign = dataset.fields.doppler_sign * c.doppler_sign;
    const Eigen::Quaterniond q(ExpSO3(c.rotation_correction_base_rad) *
                               dataset.extrinsics.T_base_radar.linear());
    io::WriteFileAtomically(opt.out, [&](std::ostream &os) {
        os << text.str() << "fields:\n  doppler_sign: " << sign << "\n"
           << "# the corrected rotation, if the correction above is trusted (see its residual):\n"
           << "# extrinsics:\n#   T_base_radar:\n#     quaternion_xyzw: "
           << Vec4(q.x(), q.y(), q.z(), q.w()) << "\n";
    });
}

// `calibrate rotation`: straight driving forward and backward. Scans the gyro sees turning are
// left out (the lever arm's velocity would tilt the axis); a drive without reversing, or turning
// most of the time, is refused, and so is an axis known worse than --max-sigma-deg.
Eigen::Matrix3d CalibrateRotationStep(const CalibrateOptions &opt, const Samples &samples,
                                      const RadarSensorModel &radar, const Eigen::Matrix3d &R_guess,
                                      int lag, std::ostringstream &comment) {
    // The ego-velocity's own direction bias left by its direction-noise compensation: an offset
    // of the velocity's direction of up to 6 % of the radar's direction noise on simulated drives
    // (docs/calibration.md); residuals cannot show it (it is the same on every scan).
    constexpr double kDirectionBiasPerNoise = 0.06;
    constexpr double kStraightRadps = 0.05;
    std::vector<Eigen::Vector3d> straight;
    std::size_t with_gyro = 0;
    for (std::size_t i = 0; i < samples.v_radar.size(); ++i) {
        const bool gyro = samples.gyro_base[i].allFinite();
        with_gyro += gyro;
        if (!gyro || std::abs(samples.gyro_base[i].z()) <= kStraightRadps)
            straight.push_back(samples.v_radar[i]);
    }
    const std::size_t used = samples.v_radar.size();
    if (with_gyro > 0 && straight.size() * 2 < used)
        Refuse(opt, "the gyro sees the vehicle turning (|yaw rate| > " + Fixed(kStraightRadps, 2) +
                        " rad/s) on " + std::to_string(used - straight.size()) + " of " +
                        std::to_string(used) +
                        " moving scans: drive straight, forward and backward");
    if (with_gyro == 0)
        std::fprintf(stderr,
                     "calibrate rotation: no IMU: turning scans cannot be left out; drive "
                     "straight\n");
    auto c = odometry::CalibrateRotation(straight, R_guess, lag);
    const double statistical_rad = c.sigma_rad;
    const double bias_rad = kDirectionBiasPerNoise *
                            DegToRad(std::max(radar.azimuth_sigma_deg, radar.elevation_sigma_deg));
    c.sigma_rad = std::hypot(statistical_rad, bias_rad);
    std::size_t forward = 0, backward = 0;
    for (const auto &v : straight) ((c.R_base_radar * v).x() > 0.0 ? forward : backward)++;
    const std::size_t fewest = std::max<std::size_t>(10, straight.size() / 10);
    if (forward < fewest || backward < fewest)
        Refuse(opt, std::to_string(forward) + " scans forward and " + std::to_string(backward) +
                        " backward (each needs " + std::to_string(fewest) +
                        "): without reversing a lateral slip or a curve reads as a mount angle; "
                        "drive straight forward and backward");
    if (RadToDeg(c.sigma_rad) > opt.max_sigma_deg)
        Refuse(opt, "the angle is unobservable on this drive: sigma " +
                        Fixed(RadToDeg(c.sigma_rad), 3) + " deg > --max-sigma-deg " +
                        Fixed(opt.max_sigma_deg, 3));
    comment << "# dorado calibrate rotation: " << c.samples << " straight scans of " << used << " ("
            << forward << " forward, " << backward << " backward), residual RMS "
            << c.rms_residual_mps << " m/s, angle sigma " << RadToDeg(c.sigma_rad)
            << " deg (statistical " << RadToDeg(statistical_rad) << " deg, errors correlated over "
            << lag << " scans; from the radar's direction noise " << RadToDeg(bias_rad)
            << " deg)\n";
    return c.R_base_radar;
}

// `calibrate sx`: a flat circle. The gyro's bias from the scans at rest is removed; a drive that
// turns less than 270 deg is refused, and so is an s_x known worse than --max-sigma.
double CalibrateSxStep(const CalibrateOptions &opt, const io::DatasetConfig &dataset,
                       const Samples &samples, const Eigen::Matrix3d &R_base_radar, int lag,
                       std::ostringstream &comment) {
    double bias = 0.0;
    if (samples.gyro_at_rest.size() >= 5) {
        for (const auto &g : samples.gyro_at_rest) bias += g.z();
        bias /= static_cast<double>(samples.gyro_at_rest.size());
    }
    std::vector<Eigen::Vector3d> v_s;
    std::vector<double> yaw;
    Samples kept;
    for (std::size_t i = 0; i < samples.v_radar.size(); ++i) {
        if (!samples.gyro_base[i].allFinite()) continue;
        v_s.push_back(R_base_radar * samples.v_radar[i]);
        yaw.push_back(samples.gyro_base[i].z() - bias);
        kept.t_s.push_back(samples.t_s[i]);
    }
    if (v_s.empty() && !samples.v_radar.empty())
        throw io::DatasetError(ImuSource(dataset) + ": no gyro sample between the usable scans (" +
                               std::to_string(samples.imu_samples) +
                               " IMU samples): s_x calibration needs the IMU's yaw rate");
    const double turn_deg = RadToDeg(TotalTurn(kept, yaw));
    if (turn_deg < 270.0)
        Refuse(opt, "the vehicle turned " + Fixed(turn_deg, 0) + " deg over the " +
                        std::to_string(v_s.size()) +
                        " moving scans; s_x needs a circle (at least 270 deg of turning)");
    auto c = odometry::CalibrateSx(v_s, yaw, lag);
    // Batch means: the spread of the estimates of five consecutive parts of the drive, a second
    // estimate of the sigma that slow errors (the ICR's wander, the gyro bias' drift) cannot hide
    // from; the larger of the two is reported.
    constexpr std::size_t kBatches = 5;
    std::vector<double> batch;
    for (std::size_t b = 0; b < kBatches; ++b) {
        const std::size_t begin = b * v_s.size() / kBatches, end = (b + 1) * v_s.size() / kBatches;
        const std::vector<Eigen::Vector3d> v(v_s.begin() + begin, v_s.begin() + end);
        const std::vector<double> w(yaw.begin() + begin, yaw.begin() + end);
        try {
            batch.push_back(odometry::CalibrateSx(v, w).s_x_m);
        } catch (const std::invalid_argument &) {  // a part without turning
        }
    }
    double sigma_batches = 0.0;
    if (batch.size() >= 3) {
        double mean = 0.0, ss = 0.0;
        for (const double x : batch) mean += x / batch.size();
        for (const double x : batch) ss += (x - mean) * (x - mean);
        sigma_batches = std::sqrt(ss / (batch.size() - 1) / batch.size());
    }
    const double sigma_residuals = c.sigma_m;
    c.sigma_m = std::max(c.sigma_m, sigma_batches);
    if (c.sigma_m > opt.max_sigma_m)
        Refuse(opt, "s_x is unobservable on this drive: " + Fixed(c.s_x_m, 3) + " +- " +
                        Fixed(c.sigma_m, 3) + " m, sigma > --max-sigma " +
                        Fixed(opt.max_sigma_m, 3) + " m");
    comment << "# dorado calibrate sx: s_x = " << c.s_x_m << " +- " << c.sigma_m
            << " m (1 sigma: the larger of " << sigma_residuals
            << " m from the residuals, correlated over " << lag << " scans, and " << sigma_batches
            << " m from " << batch.size() << " parts of the drive) from " << c.inliers << " of "
            << c.samples << " scans, " << Fixed(turn_deg, 0) << " deg of turning, residual RMS "
            << c.rms_residual_mps << " m/s, gyro bias "
            << (samples.gyro_at_rest.size() >= 5
                    ? Fixed(bias, 5) + " rad/s removed (from " +
                          std::to_string(samples.gyro_at_rest.size()) + " scans at rest)"
                    : std::string("not removed (no scans at rest)"))
            << "\n";
    return c.s_x_m;
}

void RunCalibrate(const CalibrateOptions &opt) {
    const io::DatasetConfig dataset = io::ResolveDataset(opt.dataset, opt.data, opt.choice);
    if (opt.step == "doppler-sign") {
        if (!HasImu(dataset))
            throw io::ConfigError(opt.dataset + ": key '" + ImuKey(dataset) +
                                  "': doppler-sign needs an IMU");
        return RunDopplerSign(opt, dataset);
    }
    if (opt.step == "sx" && !HasImu(dataset))
        throw io::ConfigError(opt.dataset + ": key '" + ImuKey(dataset) +
                              "': s_x calibration needs an IMU");
    Samples samples = Collect(opt, dataset);
    std::fprintf(stderr,
                 "calibrate %s: %zu scans, %zu used, %zu rejected (invalid or slower than "
                 "%.2f m/s)\n",
                 opt.step.c_str(), samples.scans, samples.v_radar.size(), samples.rejected,
                 opt.min_speed_mps);
    CheckWindow(opt, samples);
    Eigen::Isometry3d T = dataset.extrinsics.T_base_radar;
    std::ostringstream comment;
    comment << std::setprecision(4);
    const int lag = CorrelationLag(samples);
    if (opt.step == "rotation") {
        T.linear() = CalibrateRotationStep(opt, samples, dataset.radar, T.linear(), lag, comment);
    } else if (opt.step == "roll") {
        const auto c = odometry::CalibrateRoll(samples.v_radar, T.linear());
        T.linear() = c.R_base_radar;
        comment << "# dorado calibrate roll: " << c.samples << " scans, residual RMS "
                << c.rms_residual_mps << " m/s, angle sigma " << RadToDeg(c.sigma_rad) << " deg\n";
    } else {
        T.translation().x() = CalibrateSxStep(opt, dataset, samples, T.linear(), lag, comment);
    }
    std::cerr << comment.str();
    WriteSnippet(opt.out, comment.str(), T);
}

}  // namespace

void RegisterCalibrateCommand(CLI::App &app) {
    auto opt = std::make_shared<CalibrateOptions>();
    auto *cmd = app.add_subcommand(
        "calibrate",
        "Radar mounting calibration (paper IV-A). rotation: drive straight forward and backward; "
        "roll: drive with turns on flat ground (after rotation); sx: drive a flat circle (needs an "
        "IMU); doppler-sign: any motion that starts at rest (needs an IMU: the velocity change "
        "against the accelerometer). Writes a YAML snippet for the dataset description.");
    cmd->add_option("STEP", opt->step, "rotation | roll | sx | doppler-sign")
        ->required()
        ->check(OneOf({"rotation", "roll", "sx", "doppler-sign"}));
    cmd->add_option(
           "DATASET", opt->dataset,
           "dataset description (.yaml), or a recording (.bag, .db3, .mcap, rosbag2 folder)")
        ->required();
    AddDataOption(cmd, opt->data);
    cmd->add_option("--from", opt->from_s, "start [s from the first scan]");
    cmd->add_option("--to", opt->to_s, "end [s from the first scan]");
    cmd->add_option("--out", opt->out, "YAML snippet to write")->required();
    AddDatasetChoiceOptions(*cmd, opt->choice);
    cmd->add_option("--config", opt->config, "odometry settings (ego_velocity section is used)");
    cmd->add_option("--min-speed", opt->min_speed_mps, "ignore scans slower than this [m/s]");
    cmd->add_option("--window", opt->window_s, "doppler-sign: comparison window [s]");
    cmd->add_option("--rest", opt->rest_s,
                    "doppler-sign: the first seconds of IMU data, at rest (gyro bias, gravity)");
    cmd->add_option("--max-sigma", opt->max_sigma_m,
                    "sx: refuse an s_x whose 1-sigma uncertainty is larger [m]")
        ->capture_default_str();
    cmd->add_option("--max-sigma-deg", opt->max_sigma_deg,
                    "rotation: refuse an axis whose 1-sigma uncertainty is larger [deg]")
        ->capture_default_str();
    cmd->add_flag("--no-drive-checks", opt->no_drive_checks,
                  "write the result although the drive lacks the manoeuvre the step needs (a "
                  "circle for sx; straight forward and backward driving for rotation)");
    cmd->callback([opt] { RunCalibrate(*opt); });
}

}  // namespace dorado::apps
