#pragma once
/// @file ground_truth.hpp
/// The reference trajectory a lidar mapper would give: the true base pose at the lidar's rate,
/// off by a small error that drifts slowly (first-order Gauss-Markov in position and attitude).

#include <Eigen/Geometry>
#include <cstdint>
#include <random>

#include "dorado/sim/sequence_config.hpp"

namespace dorado::sim {

class MapperErrorModel {
  public:
    MapperErrorModel(const GroundTruthConfig &config, uint64_t seed);

    /// The reported pose for the true T_world_base, dt_s after the previous call.
    [[nodiscard]] Eigen::Isometry3d Perturb(const Eigen::Isometry3d &T_world_base, double dt_s);

  private:
    GroundTruthConfig config_;
    std::mt19937_64 rng_;
    Eigen::Vector3d position_error_m_ = Eigen::Vector3d::Zero();
    Eigen::Vector3d rotation_error_rad_ = Eigen::Vector3d::Zero();
    bool started_ = false;
};

}  // namespace dorado::sim
