#pragma once
// Synthetic radar scans with known truth for the odometry tests and benchmarks: static points
// spread over a Hugin-like field of view, optional moving objects, Doppler noise that grows for
// weak returns (sigma_i^2 = sigma^2 (1 + 10^((snr_reference - power_i) / 10))).

#include <Eigen/Core>
#include <cmath>
#include <random>
#include <vector>

#include "dorado/core/angles.hpp"
#include "dorado/core/radar_scan.hpp"

namespace dorado::testing {

struct SceneOptions {
    int points = 2000;
    Eigen::Vector3d v_radar = Eigen::Vector3d(5.0, 0.4, -0.2);  ///< true radar velocity
    double azimuth_half_fov_deg = 60.0;
    double elevation_half_fov_deg = 15.0;
    double doppler_sigma_mps = 0.05;  ///< noise of strong returns (0 = noise-free)
    bool heteroscedastic = true;      ///< noise grows for weak returns
    double snr_reference_db = 10.0;
    double dynamic_fraction = 0.0;
    /// true: every dynamic point belongs to one object (a bus) in a compact sector, moving with
    /// `crowd_velocity`; false: several small objects with random velocities.
    bool coherent_crowd = false;
    Eigen::Vector3d crowd_velocity = Eigen::Vector3d(-8.0, 6.0, 0.0);
    double crowd_azimuth_deg = 35.0;  ///< centre of the crowd's sector
    double crowd_width_deg = 25.0;
    uint64_t seed = 1;
};

struct SyntheticScan {
    RadarScan scan;
    std::vector<bool> dynamic;  ///< truth: point i moves
    Eigen::VectorXd sigma_mps;  ///< truth: Doppler noise of point i
    Eigen::Matrix3Xd directions;
};

inline SyntheticScan MakeScan(const SceneOptions &o) {
    std::mt19937_64 rng(o.seed);
    std::uniform_real_distribution<double> uni(-1.0, 1.0), range(2.0, 80.0), power(0.0, 40.0);
    std::normal_distribution<double> gauss(0.0, 1.0);
    const double deg = DegToRad(1.0);
    const int n = o.points;
    const int n_dynamic = static_cast<int>(std::round(o.dynamic_fraction * n));
    // Random objects: 6 of them, each with its own velocity and sector.
    std::vector<Eigen::Vector3d> object_velocity(6);
    std::vector<double> object_azimuth(6);
    for (int k = 0; k < 6; ++k) {
        object_velocity[k] = Eigen::Vector3d(uni(rng) * 12.0, uni(rng) * 12.0, uni(rng) * 0.5);
        object_azimuth[k] = uni(rng) * o.azimuth_half_fov_deg;
    }
    SyntheticScan out;
    out.scan.Resize(n);
    out.scan.has_power = true;
    out.dynamic.assign(n, false);
    out.sigma_mps.resize(n);
    out.directions.resize(3, n);
    for (int i = 0; i < n; ++i) {
        const bool dynamic = i < n_dynamic;
        double az = uni(rng) * o.azimuth_half_fov_deg;
        Eigen::Vector3d u = Eigen::Vector3d::Zero();  // the point's own velocity
        if (dynamic && o.coherent_crowd) {
            az = o.crowd_azimuth_deg + 0.5 * uni(rng) * o.crowd_width_deg;
            u = o.crowd_velocity;
        } else if (dynamic) {
            const int k = i % 6;
            az = object_azimuth[k] + uni(rng) * 4.0;
            u = object_velocity[k];
        }
        const double el = uni(rng) * o.elevation_half_fov_deg;
        const Eigen::Vector3d d(std::cos(el * deg) * std::cos(az * deg),
                                std::cos(el * deg) * std::sin(az * deg), std::sin(el * deg));
        const double r = range(rng), p = power(rng);
        const double sigma =
            o.doppler_sigma_mps *
            (o.heteroscedastic ? std::sqrt(1.0 + std::pow(10.0, (o.snr_reference_db - p) / 10.0))
                               : 1.0);
        out.scan.xyz_radar.col(i) = r * d;
        out.scan.power_db[i] = p;
        // Doppler = radial velocity of the point relative to the sensor, positive receding.
        out.scan.doppler_mps[i] = d.dot(u - o.v_radar) + sigma * gauss(rng);
        out.dynamic[i] = dynamic;
        out.sigma_mps[i] = sigma;
        out.directions.col(i) = d;
    }
    out.scan.DeriveSphericalFromXyz();
    return out;
}

}  // namespace dorado::testing
