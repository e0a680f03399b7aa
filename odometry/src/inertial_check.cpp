// The Doppler ego-velocity against the IMU's integrated acceleration (inertial_check.hpp).
#include "dorado/odometry/inertial_check.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dorado/core/lie.hpp"
#include "dorado/core/time.hpp"

namespace dorado::odometry {
namespace {

// Strapdown integration in the world frame W = the IMU frame at the first sample, gravity from the
// rest window: R_W_imu(t) from the bias-corrected gyro, V(t) = int (R_W_imu f + g_W) dt
// (trapezoid). V is the IMU's velocity up to the constant V(t0), which cancels in differences.
struct Strapdown {
    std::vector<int64_t> stamp_ns;
    std::vector<Eigen::Matrix3d> R_world_imu;
    std::vector<Eigen::Vector3d> v_world, omega_imu;

    // Index of the first sample at or after t (clamped to [1, n-1]); false outside the data.
    bool Find(int64_t t_ns, std::size_t &k) const {
        if (t_ns < stamp_ns.front() || t_ns > stamp_ns.back()) return false;
        k = std::lower_bound(stamp_ns.begin(), stamp_ns.end(), t_ns) - stamp_ns.begin();
        k = std::clamp<std::size_t>(k, 1, stamp_ns.size() - 1);
        return true;
    }
    Eigen::Vector3d VelocityAt(int64_t t_ns, std::size_t k) const {
        const double span = static_cast<double>(stamp_ns[k] - stamp_ns[k - 1]);
        const double a = span > 0 ? static_cast<double>(t_ns - stamp_ns[k - 1]) / span : 1.0;
        return (1.0 - a) * v_world[k - 1] + a * v_world[k];
    }
};

Strapdown Integrate(const std::vector<ImuSample> &imu, const Eigen::Vector3d &bias,
                    const Eigen::Vector3d &g_world) {
    Strapdown s;
    const std::size_t n = imu.size();
    s.stamp_ns.resize(n);
    s.R_world_imu.resize(n);
    s.v_world.resize(n);
    s.omega_imu.resize(n);
    s.R_world_imu[0].setIdentity();
    s.v_world[0].setZero();
    for (std::size_t k = 0; k < n; ++k) {
        s.stamp_ns[k] = imu[k].stamp_ns;
        s.omega_imu[k] = imu[k].omega_imu_radps - bias;
        if (k == 0) continue;
        const double dt = NanosToSeconds(imu[k].stamp_ns - imu[k - 1].stamp_ns);
        s.R_world_imu[k] =
            s.R_world_imu[k - 1] * ExpSO3(0.5 * (s.omega_imu[k] + s.omega_imu[k - 1]) * dt);
        const Eigen::Vector3d a0 = s.R_world_imu[k - 1] * imu[k - 1].accel_imu_mps2 + g_world;
        const Eigen::Vector3d a1 = s.R_world_imu[k] * imu[k].accel_imu_mps2 + g_world;
        s.v_world[k] = s.v_world[k - 1] + 0.5 * (a0 + a1) * dt;
    }
    return s;
}

// The Doppler velocity of the IMU point in the world frame at every scan (sign +-1, stamps
// shifted by offset_ns); NaN for scans outside the IMU data.
struct Track {
    std::vector<int64_t> stamp_ns;
    std::vector<Eigen::Vector3d> v_doppler_world, v_imu_world;
    std::vector<double> speed;
    std::vector<Eigen::Vector3d> v_radar_base;  ///< sign * R_base_radar v_radar
    std::vector<Eigen::Matrix3d> R_world_base;
};

Track Sample(const std::vector<StampedRadarVelocity> &velocities, const Strapdown &s,
             const Extrinsics &extrinsics, double sign, int64_t offset_ns) {
    const Eigen::Matrix3d R_base_radar = extrinsics.T_base_radar.linear();
    const Eigen::Matrix3d R_base_imu = extrinsics.T_base_imu.linear();
    // Lever arm from the radar to the IMU, base frame.
    const Eigen::Vector3d lever_base =
        extrinsics.T_base_imu.translation() - extrinsics.T_base_radar.translation();
    Track track;
    for (const auto &v : velocities) {
        const int64_t t = v.stamp_ns + offset_ns;
        std::size_t k = 0;
        if (!s.Find(t, k)) continue;
        // The rotation at t itself: from the sample before, at the interval's mean rate.
        const Eigen::Vector3d omega_imu = 0.5 * (s.omega_imu[k] + s.omega_imu[k - 1]);
        const Eigen::Matrix3d R_world_imu =
            s.R_world_imu[k - 1] * ExpSO3(omega_imu * NanosToSeconds(t - s.stamp_ns[k - 1]));
        const Eigen::Vector3d omega_base = R_base_imu * omega_imu;
        // v_imu = v_radar + omega x (p_imu - p_radar), base axes, then IMU axes, then world.
        const Eigen::Vector3d v_base =
            sign * (R_base_radar * v.v_radar_mps) + omega_base.cross(lever_base);
        track.stamp_ns.push_back(t);
        track.v_doppler_world.push_back(R_world_imu * R_base_imu.transpose() * v_base);
        track.v_imu_world.push_back(s.VelocityAt(t, k));
        track.speed.push_back(v.v_radar_mps.norm());
        track.v_radar_base.push_back(sign * (R_base_radar * v.v_radar_mps));
        track.R_world_base.push_back(R_world_imu * R_base_imu.transpose());
    }
    return track;
}

// Calls pair(i, j) for every comparison window with motion.
template <typename Pair>
void ForEachWindow(const Track &track, const InertialCheckConfig &config, Pair pair) {
    const auto window_ns = SecondsToNanos(config.window_s);
    std::size_t j = 0;
    for (std::size_t i = 0; i < track.stamp_ns.size(); ++i) {
        j = std::max(j, i + 1);
        while (j < track.stamp_ns.size() && track.stamp_ns[j] - track.stamp_ns[i] < window_ns) ++j;
        if (j >= track.stamp_ns.size()) break;
        if (track.stamp_ns[j] - track.stamp_ns[i] > window_ns * 3 / 2) continue;  // a gap
        if (std::max(track.speed[i], track.speed[j]) < config.min_speed_mps) continue;
        pair(i, j);
    }
}

InertialFit Fit(const Track &track, const InertialCheckConfig &config) {
    double dd = 0.0, di = 0.0, rr = 0.0;
    InertialFit fit;
    ForEachWindow(track, config, [&](std::size_t i, std::size_t j) {
        const Eigen::Vector3d d_dop = track.v_doppler_world[j] - track.v_doppler_world[i];
        const Eigen::Vector3d d_imu = track.v_imu_world[j] - track.v_imu_world[i];
        dd += d_dop.squaredNorm();
        di += d_dop.dot(d_imu);
        rr += (d_imu - d_dop).squaredNorm();
        ++fit.windows;
    });
    if (fit.windows == 0) return fit;
    fit.slope = dd > 0.0 ? di / dd : std::numeric_limits<double>::quiet_NaN();
    fit.rms_residual_mps = std::sqrt(rr / fit.windows);
    fit.rms_delta_v_mps = std::sqrt(dd / fit.windows);
    return fit;
}

// The rotation correction: with R_base_radar -> ExpSO3(phi) R_base_radar, the Doppler velocity
// R_world_base Exp(phi) u ~= R_world_base (u - Hat(u) phi) (u = the radar velocity in base), so a
// window's residual dv_imu - dv_dop is linear in phi:
//   (-R_wb(j) Hat(u_j) + R_wb(i) Hat(u_i)) phi = dv_imu - dv_dop.
// Normal equations over every window; the residual is recomputed at phi.
void FitRotation(const Track &track, const InertialCheckConfig &config, InertialCheck &check) {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    std::vector<std::pair<Eigen::Matrix3d, Eigen::Vector3d>> rows;
    ForEachWindow(track, config, [&](std::size_t i, std::size_t j) {
        const Eigen::Matrix3d A = -track.R_world_base[j] * Hat(track.v_radar_base[j]) +
                                  track.R_world_base[i] * Hat(track.v_radar_base[i]);
        const Eigen::Vector3d b = (track.v_imu_world[j] - track.v_imu_world[i]) -
                                  (track.v_doppler_world[j] - track.v_doppler_world[i]);
        H += A.transpose() * A;
        g += A.transpose() * b;
        rows.emplace_back(A, b);
    });
    if (rows.size() < 3) return;
    const Eigen::Vector3d phi = H.ldlt().solve(g);
    if (!phi.allFinite()) return;
    double rr = 0.0;
    for (const auto &[A, b] : rows) rr += (b - A * phi).squaredNorm();
    check.rotation_correction_base_rad = phi;
    check.rms_residual_corrected_mps = std::sqrt(rr / static_cast<double>(rows.size()));
}

}  // namespace

InertialCheck CompareWithImu(const std::vector<StampedRadarVelocity> &velocities,
                             const std::vector<ImuSample> &imu, const Extrinsics &extrinsics,
                             const InertialCheckConfig &config) {
    if (!(config.window_s > 0.0 && config.rest_s > 0.0 && config.time_offset_step_s > 0.0 &&
          config.max_time_offset_s >= 0.0))
        throw std::invalid_argument(
            "inertial check: window_s, rest_s and time_offset_step_s must "
            "be > 0, max_time_offset_s >= 0");
    if (imu.size() < 2) throw std::invalid_argument("inertial check: fewer than 2 IMU samples");
    InertialCheck check;
    const auto rest_end = imu.front().stamp_ns + SecondsToNanos(config.rest_s);
    int rest = 0;
    for (const auto &sample : imu) {
        if (sample.stamp_ns > rest_end) break;
        check.gyro_bias_imu_radps += sample.omega_imu_radps;
        check.specific_force_at_rest_imu_mps2 += sample.accel_imu_mps2;
        ++rest;
    }
    if (rest < 2) throw std::invalid_argument("inertial check: fewer than 2 IMU samples at rest");
    check.gyro_bias_imu_radps /= rest;
    check.specific_force_at_rest_imu_mps2 /= rest;
    for (int k = 0; k < rest; ++k)
        check.rest_gyro_rms_radps +=
            (imu[k].omega_imu_radps - check.gyro_bias_imu_radps).squaredNorm();
    check.rest_gyro_rms_radps = std::sqrt(check.rest_gyro_rms_radps / rest);

    // At rest f = -g: the world's gravity is minus the rest's specific force (W = IMU at t0).
    const Strapdown s =
        Integrate(imu, check.gyro_bias_imu_radps, -check.specific_force_at_rest_imu_mps2);
    check.as_given = Fit(Sample(velocities, s, extrinsics, 1.0, 0), config);
    check.flipped = Fit(Sample(velocities, s, extrinsics, -1.0, 0), config);
    if (check.as_given.windows > 0)
        check.doppler_sign =
            check.as_given.rms_residual_mps <= check.flipped.rms_residual_mps ? 1 : -1;
    const double sign = check.doppler_sign < 0 ? -1.0 : 1.0;
    check.at_best_offset = check.doppler_sign < 0 ? check.flipped : check.as_given;
    FitRotation(Sample(velocities, s, extrinsics, sign, 0), config, check);
    const int steps =
        static_cast<int>(std::floor(config.max_time_offset_s / config.time_offset_step_s));
    for (int i = -steps; i <= steps; ++i) {
        if (i == 0) continue;
        const double offset_s = i * config.time_offset_step_s;
        const InertialFit fit =
            Fit(Sample(velocities, s, extrinsics, sign, SecondsToNanos(offset_s)), config);
        if (fit.windows > 0 && !(fit.rms_residual_mps >= check.at_best_offset.rms_residual_mps)) {
            check.at_best_offset = fit;
            check.best_time_offset_s = offset_s;
        }
    }
    return check;
}

}  // namespace dorado::odometry
