#include "dorado/sim/terrain.hpp"

#include <cmath>
#include <random>

namespace dorado::sim {

namespace {

/// n waves with random directions, wavelengths in [0.6, 1.7] x the nominal one and amplitudes
/// whose sum of squares gives an RMS height of height_m / sqrt(2).
void AddWaves(int n, double height_m, double wavelength_m, std::mt19937_64 &rng,
              std::vector<double> &out_params) {
    std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI);
    std::uniform_real_distribution<double> scale(0.6, 1.7);
    for (int k = 0; k < n; ++k) {
        const double direction = angle(rng);
        const double wavelength = wavelength_m * scale(rng);
        const double phase = angle(rng);
        out_params.insert(out_params.end(), {direction, wavelength, phase,
                                             height_m / std::sqrt(static_cast<double>(n))});
    }
}

}  // namespace

Terrain::Terrain(const TerrainConfig &config, uint64_t seed) {
    std::mt19937_64 rng(seed ^ 0x7e77a1full);
    std::vector<double> params;
    auto to_waves = [&](std::vector<Wave> &waves) {
        for (std::size_t i = 0; i + 3 < params.size(); i += 4) {
            const double k = 2.0 * M_PI / params[i + 1];
            waves.push_back({k * Eigen::Vector2d(std::cos(params[i]), std::sin(params[i])),
                             params[i + 3], params[i + 2]});
        }
        params.clear();
    };
    AddWaves(6, config.hill_height_m, config.hill_wavelength_m, rng, params);
    // Ridges a few vehicle lengths wide tilt the vehicle sideways whatever its heading.
    AddWaves(6, config.side_slope_height_m, 12.0, rng, params);
    to_waves(hills_);
    AddWaves(10, config.roughness_m, config.roughness_wavelength_m, rng, params);
    to_waves(bumps_);
}

double Terrain::Sum(const std::vector<Wave> &waves, double x, double y) {
    double h = 0.0;
    for (const auto &w : waves) {
        h += w.amplitude * std::sin(w.wavevector.x() * x + w.wavevector.y() * y + w.phase);
    }
    return h;
}

double Terrain::Height(double x, double y) const {
    return Sum(hills_, x, y) + Sum(bumps_, x, y);
}

double Terrain::SmoothHeight(double x, double y) const {
    return Sum(hills_, x, y);
}

Eigen::Vector3d Terrain::Normal(double x, double y) const {
    Eigen::Vector2d gradient = Eigen::Vector2d::Zero();
    for (const auto &w : hills_) {
        gradient += w.amplitude * w.wavevector *
                    std::cos(w.wavevector.x() * x + w.wavevector.y() * y + w.phase);
    }
    return Eigen::Vector3d(-gradient.x(), -gradient.y(), 1.0).normalized();
}

}  // namespace dorado::sim
