#pragma once
/// @file terrain.hpp
/// The ground: a smooth height field z = h(x, y) in the world frame (hills of a given height and
/// wavelength, plus small bumps that the wheels feel and that make the vehicle vibrate).

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "dorado/sim/sequence_config.hpp"

namespace dorado::sim {

class Terrain {
  public:
    Terrain(const TerrainConfig &config, uint64_t seed);

    /// Height of the ground [m] at (x, y), including the small bumps.
    [[nodiscard]] double Height(double x, double y) const;
    /// Height of the smooth hills only (what static objects stand on).
    [[nodiscard]] double SmoothHeight(double x, double y) const;
    /// Upward unit normal of the smooth surface.
    [[nodiscard]] Eigen::Vector3d Normal(double x, double y) const;

  private:
    /// h = sum_k a_k sin(k_k . (x, y) + phase_k)
    struct Wave {
        Eigen::Vector2d wavevector;
        double amplitude;
        double phase;
    };
    static double Sum(const std::vector<Wave> &waves, double x, double y);
    std::vector<Wave> hills_;
    std::vector<Wave> bumps_;
};

}  // namespace dorado::sim
