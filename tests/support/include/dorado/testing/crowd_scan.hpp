#pragma once
// Synthetic radar scans built like recorded crowded street scans, with known truth, for the
// ego-velocity benchmarks: a ground-heavy static world (road returns at low elevation, weak),
// static structure around it, several coherent movers (cars, a bus, cyclists) that together hold
// 25-40 % of the points, clutter with random Doppler, and multipath ghosts (double bounces off the
// ego vehicle, movers mirrored in a side wall). Doppler noise grows for weak returns as in
// tests/odometry: sigma_i^2 = sigma^2 (1 + 10^((snr_reference - power_i) / 10)).

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "dorado/core/angles.hpp"
#include "dorado/testing/doppler_scan.hpp"

namespace dorado::testing {

/// What each point of a crowd scan is (the truth).
enum class CrowdPointKind { kGround, kStructure, kMover, kClutter, kGhost };

struct CrowdScene {
    SyntheticScan scan;  ///< scan, truth mask (non-static = dynamic), sigma
    std::vector<CrowdPointKind> kind;
    Eigen::Vector3d v_radar;  ///< true radar velocity
};

struct CrowdOptions {
    int points = 2000;
    uint64_t seed = 1;
    double doppler_sigma_mps = 0.05;
    double snr_reference_db = 10.0;
    double azimuth_half_fov_deg = 60.0;
    double elevation_half_fov_deg = 20.0;
    double sensor_height_m = 1.6;
    /// Fraction of the points on the movers; < 0: drawn in [0.25, 0.40] (the random stream is the
    /// same either way).
    double mover_fraction = -1.0;
};

namespace detail {

struct Mover {
    Eigen::Vector3d velocity;  // world velocity seen in the radar frame (radar does not rotate)
    double azimuth_deg, width_deg, elevation_deg, range_m;
    double share;  // fraction of the mover points
};

inline Eigen::Vector3d Direction(double az_deg, double el_deg) {
    const double a = DegToRad(az_deg), e = DegToRad(el_deg);
    return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

}  // namespace detail

/// One crowded scan; every random choice comes from `o.seed`.
inline CrowdScene MakeCrowdScan(const CrowdOptions &o) {
    std::mt19937_64 rng(o.seed);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::normal_distribution<double> gauss(0.0, 1.0);
    auto uni = [&](double lo, double hi) { return lo + (hi - lo) * u01(rng); };
    CrowdScene out;
    out.v_radar = Eigen::Vector3d(uni(3.0, 15.0), uni(-0.5, 0.5), uni(-0.3, 0.3));
    const double drawn_mover_fraction = uni(0.25, 0.40), clutter_fraction = uni(0.04, 0.08),
                 ghost_fraction = uni(0.03, 0.06);
    const double mover_fraction = o.mover_fraction >= 0.0 ? o.mover_fraction : drawn_mover_fraction;
    // 3-6 coherent movers: oncoming and same-direction traffic, one large (a bus or a truck).
    std::vector<detail::Mover> movers(3 + static_cast<int>(u01(rng) * 4));
    double share_sum = 0.0;
    for (std::size_t k = 0; k < movers.size(); ++k) {
        auto &m = movers[k];
        const double speed = uni(2.0, 16.0) * (u01(rng) < 0.5 ? -1.0 : 1.0);
        const double heading = uni(-0.3, 0.3) + (u01(rng) < 0.2 ? M_PI / 2 : 0.0);
        m.velocity = Eigen::Vector3d(speed * std::cos(heading), speed * std::sin(heading), 0.0);
        m.azimuth_deg = uni(-0.8, 0.8) * o.azimuth_half_fov_deg;
        m.range_m = uni(6.0, 50.0);
        m.width_deg = (k == 0 ? 20.0 : 6.0) * 10.0 / m.range_m + 2.0;  // the first one is big
        m.elevation_deg = RadToDeg(std::atan2(1.0 - o.sensor_height_m, m.range_m));
        m.share = k == 0 ? 3.0 : uni(0.5, 1.5);
        share_sum += m.share;
    }
    const int n = o.points;
    const int n_mover = static_cast<int>(std::round(mover_fraction * n));
    const int n_clutter = static_cast<int>(std::round(clutter_fraction * n));
    const int n_ghost = static_cast<int>(std::round(ghost_fraction * n));
    const int n_static = n - n_mover - n_clutter - n_ghost;
    const int n_ground = static_cast<int>(0.55 * n_static);  // ground-heavy
    const double tan_fov = std::tan(DegToRad(o.elevation_half_fov_deg));

    auto &s = out.scan;
    s.scan.Resize(n);
    s.scan.has_power = true;
    s.dynamic.assign(n, false);
    s.sigma_mps.resize(n);
    s.directions.resize(3, n);
    out.kind.resize(n);
    std::size_t mover = 0;
    double mover_cum = movers[0].share / share_sum;
    for (int i = 0; i < n; ++i) {
        CrowdPointKind kind = CrowdPointKind::kStructure;
        if (i < n_ground)
            kind = CrowdPointKind::kGround;
        else if (i >= n_static && i < n_static + n_mover)
            kind = CrowdPointKind::kMover;
        else if (i >= n_static + n_mover && i < n_static + n_mover + n_clutter)
            kind = CrowdPointKind::kClutter;
        else if (i >= n_static + n_mover + n_clutter)
            kind = CrowdPointKind::kGhost;
        Eigen::Vector3d d, u = Eigen::Vector3d::Zero();  // direction, the point's own velocity
        double range = 0.0, power = 0.0, doppler = 0.0;
        bool doppler_set = false;
        const double az = uni(-1.0, 1.0) * o.azimuth_half_fov_deg;
        switch (kind) {
            case CrowdPointKind::kGround: {
                const double r_min = o.sensor_height_m / tan_fov;
                range = r_min + (40.0 - r_min) * std::pow(u01(rng), 2.0);  // dense near
                const double el = -RadToDeg(std::asin(o.sensor_height_m / range));
                d = detail::Direction(az, el + 0.3 * gauss(rng));
                power = uni(-2.0, 18.0);  // grazing: weak
                break;
            }
            case CrowdPointKind::kStructure:
                d = detail::Direction(az, uni(-0.3, 1.0) * o.elevation_half_fov_deg);
                range = uni(5.0, 90.0);
                power = uni(5.0, 40.0);
                break;
            case CrowdPointKind::kMover: {
                const int j = i - n_static;
                while (mover + 1 < movers.size() && j >= mover_cum * n_mover)
                    mover_cum += movers[++mover].share / share_sum;
                const auto &m = movers[mover];
                d = detail::Direction(m.azimuth_deg + 0.5 * uni(-1.0, 1.0) * m.width_deg,
                                      m.elevation_deg + uni(-4.0, 6.0));
                u = m.velocity;
                range = m.range_m + uni(-2.0, 2.0);
                power = uni(15.0, 40.0);  // vehicles are strong reflectors
                break;
            }
            case CrowdPointKind::kClutter:
                d = detail::Direction(az, uni(-1.0, 1.0) * o.elevation_half_fov_deg);
                range = uni(2.0, 80.0);
                power = uni(-5.0, 12.0);
                doppler = uni(-20.0, 20.0);
                doppler_set = true;
                break;
            case CrowdPointKind::kGhost: {
                // Multipath: a static point's double bounce off the ego vehicle (same direction,
                // twice the range and the Doppler), or a mover's image behind a side wall
                // (mirrored azimuth, the mover's Doppler). A static point's image in a static
                // wall is itself static, so it is not simulated as a ghost.
                const auto &m = movers[static_cast<std::size_t>(u01(rng) * movers.size())];
                if (u01(rng) < 0.5) {
                    d = detail::Direction(az, uni(-0.3, 1.0) * o.elevation_half_fov_deg);
                    doppler = -2.0 * d.dot(out.v_radar);
                    range = uni(10.0, 120.0);
                } else {
                    const Eigen::Vector3d source = detail::Direction(
                        m.azimuth_deg + 0.5 * uni(-1.0, 1.0) * m.width_deg, m.elevation_deg);
                    doppler = source.dot(m.velocity - out.v_radar);
                    d = detail::Direction(
                        std::clamp(-m.azimuth_deg + uni(-5.0, 5.0), -o.azimuth_half_fov_deg,
                                   o.azimuth_half_fov_deg),
                        m.elevation_deg + uni(-3.0, 3.0));
                    range = m.range_m + uni(5.0, 30.0);
                }
                power = uni(-3.0, 10.0);
                doppler_set = true;
                break;
            }
        }
        const double sigma = o.doppler_sigma_mps *
                             std::sqrt(1.0 + std::pow(10.0, (o.snr_reference_db - power) / 10.0));
        if (!doppler_set) doppler = d.dot(u - out.v_radar);
        s.scan.xyz_radar.col(i) = range * d;
        s.scan.power_db[i] = power;
        s.scan.doppler_mps[i] = doppler + sigma * gauss(rng);
        s.dynamic[i] = kind != CrowdPointKind::kGround && kind != CrowdPointKind::kStructure;
        s.sigma_mps[i] = sigma;
        s.directions.col(i) = d;
        out.kind[i] = kind;
    }
    // Recorded scans are not sorted by what the points are.
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), rng);
    const CrowdScene sorted = out;
    for (int i = 0; i < n; ++i) {
        const int j = order[i];
        s.scan.xyz_radar.col(i) = sorted.scan.scan.xyz_radar.col(j);
        s.scan.power_db[i] = sorted.scan.scan.power_db[j];
        s.scan.doppler_mps[i] = sorted.scan.scan.doppler_mps[j];
        s.dynamic[i] = sorted.scan.dynamic[j];
        s.sigma_mps[i] = sorted.scan.sigma_mps[j];
        s.directions.col(i) = sorted.scan.directions.col(j);
        out.kind[i] = sorted.kind[j];
    }
    s.scan.DeriveSphericalFromXyz();
    return out;
}

}  // namespace dorado::testing
