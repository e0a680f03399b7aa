// `dorado calibrate rotation|roll|sx DATASET --out FILE.yaml`: the paper's calibration (IV-A).
#include <Eigen/Geometry>
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
};

/// Per valid, moving scan in the time range: the radar velocity and the mean gyro rate in the base
/// frame over the interval since the previous scan (NaN without IMU).
struct Samples {
    std::vector<Eigen::Vector3d> v_radar, gyro_base;
    std::size_t scans = 0, rejected = 0, imu_samples = 0;
};

Samples Collect(const CalibrateOptions &opt, const io::DatasetConfig &dataset) {
    odometry::EgoVelocityConfig ego;
    if (!opt.config.empty()) ego = dorado::config::LoadOdometryConfig(opt.config).ego_velocity;
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
        if ((opt.from_s >= 0 && t < opt.from_s) || (opt.to_s >= 0 && t > opt.to_s)) continue;
        const auto r = estimator.Estimate(event.scan);
        if (!r.valid() || r.v_radar_mps.norm() < opt.min_speed_mps) {
            ++out.rejected;
            continue;
        }
        out.v_radar.push_back(r.v_radar_mps);
        out.gyro_base.push_back(gyro);
    }
    progress.Finish();
    return out;
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
    const Samples samples = Collect(opt, dataset);
    std::fprintf(stderr,
                 "calibrate %s: %zu scans, %zu used, %zu rejected (invalid or slower than "
                 "%.2f m/s)\n",
                 opt.step.c_str(), samples.scans, samples.v_radar.size(), samples.rejected,
                 opt.min_speed_mps);
    Eigen::Isometry3d T = dataset.extrinsics.T_base_radar;
    std::ostringstream comment;
    comment << std::setprecision(4);
    if (opt.step == "rotation" || opt.step == "roll") {
        const auto c = opt.step == "rotation"
                           ? odometry::CalibrateRotation(samples.v_radar, T.linear())
                           : odometry::CalibrateRoll(samples.v_radar, T.linear());
        T.linear() = c.R_base_radar;
        comment << "# dorado calibrate " << opt.step << ": " << c.samples << " scans, residual RMS "
                << c.rms_residual_mps << " m/s, angle sigma " << RadToDeg(c.sigma_rad) << " deg\n";
    } else {
        std::vector<Eigen::Vector3d> v_s;
        std::vector<double> yaw;
        for (std::size_t i = 0; i < samples.v_radar.size(); ++i) {
            if (!samples.gyro_base[i].allFinite()) continue;
            v_s.push_back(T.linear() * samples.v_radar[i]);
            yaw.push_back(samples.gyro_base[i].z());
        }
        if (v_s.empty() && !samples.v_radar.empty())
            throw io::DatasetError(ImuSource(dataset) +
                                   ": no gyro sample between the usable scans (" +
                                   std::to_string(samples.imu_samples) +
                                   " IMU samples): s_x calibration needs the IMU's yaw rate");
        const auto c = odometry::CalibrateSx(v_s, yaw);
        T.translation().x() = c.s_x_m;
        comment << "# dorado calibrate sx: s_x = " << c.s_x_m << " +- " << c.sigma_m << " m from "
                << c.inliers << " of " << c.samples << " scans, residual RMS " << c.rms_residual_mps
                << " m/s\n";
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
    cmd->callback([opt] { RunCalibrate(*opt); });
}

}  // namespace dorado::apps
