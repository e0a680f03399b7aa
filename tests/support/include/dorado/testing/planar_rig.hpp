#pragma once
// Several 2D radars on a vehicle driving through a fixed world of static landmarks, with exact
// truth: the vehicle's pose and twist at any time (constant speed, yaw rate varying as a sine),
// and each radar's scan at its own stamp rendered from its *true* mount, which may differ from
// the published one by a yaw offset. Doppler of a static point: -d . v_radar (paper eq. 1).

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "dorado/core/angles.hpp"
#include "dorado/core/radar_scan.hpp"

namespace dorado::testing {

inline Eigen::Isometry3d PlanarMount(double x, double y, double yaw_deg) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() << x, y, 0.0;
    T.linear() = Eigen::AngleAxisd(DegToRad(yaw_deg), Eigen::Vector3d::UnitZ()).matrix();
    return T;
}

struct PlanarRig {
    double speed_mps = 8.0;
    double yaw_rate_amplitude_radps = 0.15;
    double yaw_rate_period_s = 12.0;
    double doppler_sigma_mps = 0.03;
    double max_range_m = 60.0;
    double half_fov_deg = 75.0;
    /// The published mounts (what the estimator is told) and the true yaw offsets [deg].
    std::vector<Eigen::Isometry3d> published = {
        PlanarMount(3.6, 0.0, 0.0), PlanarMount(2.5, 0.9, 85.0), PlanarMount(2.5, -0.9, -85.0),
        PlanarMount(-0.5, 0.8, 150.0)};
    std::vector<double> yaw_offset_deg = std::vector<double>(4, 0.0);
    std::vector<Eigen::Vector2d> landmarks;

    explicit PlanarRig(uint64_t seed = 7, int landmarks_count = 4000) {
        std::mt19937_64 rng(seed);
        std::uniform_real_distribution<double> x(-100.0, 320.0), y(-160.0, 160.0);
        for (int i = 0; i < landmarks_count; ++i) landmarks.emplace_back(x(rng), y(rng));
    }

    /// (v_x, v_y, yaw rate) of the base at time t (no sideslip: an Ackermann vehicle).
    [[nodiscard]] Eigen::Vector3d Twist(double t) const {
        return {speed_mps, 0.0,
                yaw_rate_amplitude_radps * std::sin(2.0 * M_PI * t / yaw_rate_period_s)};
    }
    /// Heading at time t: the integral of the yaw rate from 0.
    [[nodiscard]] double Heading(double t) const {
        const double w = 2.0 * M_PI / yaw_rate_period_s;
        return yaw_rate_amplitude_radps * (1.0 - std::cos(w * t)) / w;
    }
    /// T_world_base at time t (position integrated finely from the start at the origin).
    [[nodiscard]] Eigen::Isometry3d Pose(double t) const {
        Eigen::Vector2d p = Eigen::Vector2d::Zero();
        const int steps = std::max(1, static_cast<int>(t / 0.001));
        const double h = t / steps;
        for (int i = 0; i < steps; ++i) {
            const double a = Heading((i + 0.5) * h);
            p += speed_mps * h * Eigen::Vector2d(std::cos(a), std::sin(a));
        }
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.translation() << p.x(), p.y(), 0.0;
        T.linear() = Eigen::AngleAxisd(Heading(t), Eigen::Vector3d::UnitZ()).matrix();
        return T;
    }
    [[nodiscard]] Eigen::Isometry3d TrueMount(std::size_t k) const {
        Eigen::Isometry3d T = published[k];
        T.linear() =
            T.linear() *
            Eigen::AngleAxisd(DegToRad(yaw_offset_deg[k]), Eigen::Vector3d::UnitZ()).matrix();
        return T;
    }
    /// Radar k's scan at time t (its own frame, z = 0), with Doppler noise.
    [[nodiscard]] RadarScan Scan(std::size_t k, double t, uint64_t seed) const {
        const Eigen::Isometry3d T_world_radar = Pose(t) * TrueMount(k);
        const Eigen::Isometry3d T_base_radar = TrueMount(k);
        const Eigen::Vector3d x = Twist(t);
        const Eigen::Vector3d s = T_base_radar.translation();
        const Eigen::Vector3d v_base_at_radar(x(0) - x(2) * s.y(), x(1) + x(2) * s.x(), 0.0);
        const Eigen::Vector3d v_radar = T_base_radar.linear().transpose() * v_base_at_radar;
        std::mt19937_64 rng(seed);
        std::normal_distribution<double> noise(0.0, doppler_sigma_mps);
        std::vector<Eigen::Vector3d> points;
        const Eigen::Isometry3d T_radar_world = T_world_radar.inverse();
        for (const Eigen::Vector2d &l : landmarks) {
            const Eigen::Vector3d p = T_radar_world * Eigen::Vector3d(l.x(), l.y(), 0.0);
            const double r = p.head<2>().norm();
            if (r < 1.0 || r > max_range_m) continue;
            if (std::abs(std::atan2(p.y(), p.x())) > DegToRad(half_fov_deg)) continue;
            points.emplace_back(p.x(), p.y(), 0.0);
        }
        RadarScan scan;
        scan.stamp_ns = static_cast<int64_t>(std::llround(t * 1e9));
        scan.Resize(static_cast<Eigen::Index>(points.size()));
        scan.has_power = false;
        for (std::size_t i = 0; i < points.size(); ++i) {
            const auto j = static_cast<Eigen::Index>(i);
            scan.xyz_radar.col(j) = points[i];
            scan.doppler_mps(j) = -points[i].normalized().dot(v_radar) + noise(rng);
            scan.power_db(j) = 0.0;
        }
        scan.DeriveSphericalFromXyz();
        return scan;
    }
};

}  // namespace dorado::testing
