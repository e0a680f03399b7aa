#pragma once
// Test helper: a synthetic street scene seen by a 4D radar (sparse, noisy, with ghosts and movers),
// with exact poses and twists, so that the mapper's results can be checked against the truth.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "dorado/core/lie.hpp"
#include "dorado/core/radar_scan.hpp"

namespace dorado::testing {

/// A dense cloud of static world points: two building rows along a street with gaps, the ground,
/// poles and parked boxes (3D structure in every direction, as in a town).
inline Eigen::Matrix3Xd MakeStreetWorld(unsigned seed, double length_m = 240.0) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Eigen::Vector3d> pts;
    for (double x = -60.0; x < length_m; x += 0.35) {
        for (int side : {-1, 1}) {
            // Facades at |y| = 9..13 m that step in and out every 12 m, 8 m high, with doorways.
            const double y =
                side * (9.0 + 4.0 * (static_cast<int>(std::floor(x / 12.0)) % 2 == 0 ? 0.0 : 1.0));
            if (std::fmod(x + 600.0, 30.0) < 3.0) continue;  // side streets
            for (double z = 0.0; z < 8.0; z += 0.5)
                pts.emplace_back(x, y + 0.05 * u(rng), z + 0.2 * u(rng));
        }
        for (double y = -9.0; y <= 9.0; y += 1.5) pts.emplace_back(x, y, 0.05 * u(rng));  // ground
    }
    // The faces where the facades step in and out (they face along the street).
    for (double x = 0.0; x < length_m; x += 12.0)
        for (int side : {-1, 1})
            for (double y = 9.0; y <= 13.0; y += 0.35)
                for (double z = 0.0; z < 8.0; z += 0.5) pts.emplace_back(x, side * y, z);
    // Poles every ~15 m on both sides, and boxes (parked cars) between them.
    for (double x = -55.0; x < length_m; x += 15.0) {
        for (int side : {-1, 1}) {
            for (double z = 0.0; z < 5.0; z += 0.2)
                for (int k = 0; k < 6; ++k)
                    pts.emplace_back(x + 0.15 * std::cos(k), side * 7.0 + 0.15 * std::sin(k), z);
            for (double bx = 0.0; bx < 4.0; bx += 0.3)
                for (double bz = 0.0; bz < 1.5; bz += 0.3) {
                    pts.emplace_back(x + 5.0 + bx, side * 5.5, bz);
                    pts.emplace_back(x + 5.0 + bx, side * 4.0, bz);
                }
        }
    }
    Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(pts.size()));
    for (std::size_t i = 0; i < pts.size(); ++i) out.col(static_cast<Eigen::Index>(i)) = pts[i];
    return out;
}

struct RadarSimOptions {
    int points_per_scan = 5000;
    double max_range_m = 80.0;
    double half_fov_azimuth_rad = 1.2;
    double half_fov_elevation_rad = 0.35;
    double range_sigma_m = 0.08;     ///< radial noise
    double angle_sigma_rad = 0.006;  ///< angular noise (~0.5 m lateral at 80 m)
    double doppler_sigma_mps = 0.05;
    double ghost_fraction = 0.03;  ///< random points with random Doppler
};

/// One radar scan of `world` from T_world_base with base twist (v_base, omega_base); every point
/// is static except `movers`, which move with velocity v_world_movers (labelled in is_static).
inline RadarScan SimulateScan(const Eigen::Matrix3Xd &world, const Eigen::Isometry3d &T_world_base,
                              const Eigen::Isometry3d &T_base_radar, const Eigen::Vector3d &v_base,
                              const Eigen::Vector3d &omega_base, const Eigen::Matrix3Xd &movers,
                              const Eigen::Vector3d &v_world_movers, const RadarSimOptions &o,
                              std::mt19937 &rng, Eigen::Array<bool, Eigen::Dynamic, 1> *is_static) {
    const Eigen::Isometry3d T_radar_world = (T_world_base * T_base_radar).inverse();
    // Velocity of the radar, radar frame (rigid body: v_s = v_b + omega x t_base_radar).
    const Eigen::Vector3d v_radar =
        T_base_radar.linear().transpose() * (v_base + omega_base.cross(T_base_radar.translation()));
    const Eigen::Vector3d v_movers_radar = T_radar_world.linear() * v_world_movers;
    std::vector<Eigen::Vector3d> visible;
    std::vector<bool> visible_static;
    auto consider = [&](const Eigen::Vector3d &p_world, bool is_static_point) {
        const Eigen::Vector3d p = T_radar_world * p_world;
        const double r = p.norm();
        if (r < 1.0 || r > o.max_range_m) return;
        if (std::abs(std::atan2(p.y(), p.x())) > o.half_fov_azimuth_rad) return;
        if (std::abs(std::asin(p.z() / r)) > o.half_fov_elevation_rad) return;
        visible.push_back(p);
        visible_static.push_back(is_static_point);
    };
    for (Eigen::Index i = 0; i < world.cols(); ++i) consider(world.col(i), true);
    for (Eigen::Index i = 0; i < movers.cols(); ++i) consider(movers.col(i), false);

    std::uniform_int_distribution<std::size_t> pick(0, visible.empty() ? 0 : visible.size() - 1);
    std::normal_distribution<double> n01(0.0, 1.0);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int n = o.points_per_scan;
    RadarScan scan;
    scan.Resize(n);
    if (is_static) is_static->resize(n);
    for (int k = 0; k < n; ++k) {
        Eigen::Vector3d p;
        double doppler;
        bool static_point = true;
        if (u(rng) < o.ghost_fraction || visible.empty()) {
            // A multipath ghost: anywhere in the field of view, with a Doppler that fits nothing.
            const double r = 5.0 + u(rng) * (o.max_range_m - 5.0);
            const double az = (2.0 * u(rng) - 1.0) * o.half_fov_azimuth_rad;
            const double el = (2.0 * u(rng) - 1.0) * o.half_fov_elevation_rad;
            p = r * Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                                    std::sin(el));
            doppler = (2.0 * u(rng) - 1.0) * 10.0;
            static_point = false;
        } else {
            const std::size_t j = pick(rng);
            p = visible[j];
            const Eigen::Vector3d d = p.normalized();
            static_point = visible_static[j];
            // Doppler: radial velocity of the point relative to the sensor (paper eq. 1).
            const Eigen::Vector3d v_rel =
                (static_point ? Eigen::Vector3d::Zero() : v_movers_radar) - v_radar;
            doppler = d.dot(v_rel) + o.doppler_sigma_mps * n01(rng);
            // Range and angle noise.
            const double r = p.norm() + o.range_sigma_m * n01(rng);
            const Eigen::Vector3d dn =
                (d + o.angle_sigma_rad * Eigen::Vector3d(n01(rng), n01(rng), n01(rng)))
                    .normalized();
            p = r * dn;
        }
        scan.xyz_radar.col(k) = p;
        scan.doppler_mps(k) = doppler;
        scan.power_db(k) = 10.0;
        if (is_static) (*is_static)(k) = static_point;
    }
    scan.DeriveSphericalFromXyz();
    return scan;
}

/// A smooth drive along the street: speed 6-9 m/s, gentle yaw weaving, a little pitch and roll.
struct TruthSample {
    double t;
    Eigen::Isometry3d T_world_base;
    Eigen::Vector3d v_base, omega_base;
};

inline std::vector<TruthSample> MakeDrive(int scans, double dt) {
    std::vector<TruthSample> out;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    const int substeps = 20;
    for (int k = 0; k < scans; ++k) {
        const double t = k * dt;
        auto twist_at = [](double s, Eigen::Vector3d &v, Eigen::Vector3d &w) {
            v = Eigen::Vector3d(7.5 + 1.5 * std::sin(0.4 * s), 0.0, 0.0);
            w = Eigen::Vector3d(0.02 * std::sin(1.3 * s), 0.01 * std::sin(0.9 * s),
                                0.08 * std::sin(0.5 * s));
        };
        Eigen::Vector3d v, w;
        twist_at(t, v, w);
        out.push_back({t, T, v, w});
        for (int j = 0; j < substeps; ++j) {
            const double s = t + (j + 0.5) * dt / substeps;
            twist_at(s, v, w);
            Vector6d xi;
            xi << v * dt / substeps, w * dt / substeps;
            T = T * ExpSE3(xi);
        }
    }
    return out;
}

}  // namespace dorado::testing
