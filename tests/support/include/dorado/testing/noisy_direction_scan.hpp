#pragma once
// A ground-heavy static scene seen by a radar whose directions are noisy: the true Doppler comes
// from the true direction, the point is written at the measured (noisy) azimuth and elevation,
// as a real radar reports it. Optionally the Doppler is aliased into [-v_unamb, v_unamb).

#include <Eigen/Core>
#include <cmath>
#include <random>

#include "dorado/core/angles.hpp"
#include "dorado/core/radar_scan.hpp"

namespace dorado::testing {

struct NoisyDirectionOptions {
    int points = 800;
    Eigen::Vector3d v_radar = Eigen::Vector3d(10.0, 0.0, 0.0);
    double azimuth_half_fov_deg = 50.0;
    /// A share of the points on the road ahead (elevation -15..-2 deg), the rest -2..+10 deg.
    double ground_fraction = 0.7;
    double doppler_sigma_mps = 0.05;
    double azimuth_sigma_deg = 0.5;
    double elevation_sigma_deg = 2.0;
    double doppler_unambiguous_mps = 0.0;  ///< > 0: aliased Doppler
    uint64_t seed = 1;
};

struct NoisyDirectionScan {
    RadarScan scan;
    Eigen::Matrix3Xd true_directions;
};

inline NoisyDirectionScan MakeNoisyDirectionScan(const NoisyDirectionOptions &o) {
    std::mt19937_64 rng(o.seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    std::normal_distribution<double> gauss(0.0, 1.0);
    const double deg = DegToRad(1.0);
    NoisyDirectionScan out;
    out.scan.Resize(o.points);
    out.scan.has_power = false;
    out.true_directions.resize(3, o.points);
    const auto direction = [](double az, double el) {
        return Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                               std::sin(el));
    };
    for (int i = 0; i < o.points; ++i) {
        const double az = (2.0 * uni(rng) - 1.0) * o.azimuth_half_fov_deg * deg;
        const double el =
            (uni(rng) < o.ground_fraction ? -15.0 + 13.0 * uni(rng) : -2.0 + 12.0 * uni(rng)) * deg;
        const Eigen::Vector3d d = direction(az, el);
        const double range = 3.0 + 60.0 * uni(rng);
        double doppler = -d.dot(o.v_radar) + o.doppler_sigma_mps * gauss(rng);
        if (o.doppler_unambiguous_mps > 0.0) {
            const double span = 2.0 * o.doppler_unambiguous_mps;
            doppler -= span * std::floor((doppler + o.doppler_unambiguous_mps) / span);
        }
        const Eigen::Vector3d d_measured = direction(az + o.azimuth_sigma_deg * deg * gauss(rng),
                                                     el + o.elevation_sigma_deg * deg * gauss(rng));
        out.scan.xyz_radar.col(i) = range * d_measured;
        out.scan.doppler_mps[i] = doppler;
        out.scan.power_db[i] = 0.0;
        out.true_directions.col(i) = d;
    }
    out.scan.DeriveSphericalFromXyz();
    return out;
}

}  // namespace dorado::testing
