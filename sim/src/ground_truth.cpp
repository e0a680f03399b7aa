#include "dorado/sim/ground_truth.hpp"

#include <cmath>

#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"

namespace dorado::sim {

MapperErrorModel::MapperErrorModel(const GroundTruthConfig &config, uint64_t seed)
    : config_(config), rng_(seed ^ 0x6a7e0ull) {}

Eigen::Isometry3d MapperErrorModel::Perturb(const Eigen::Isometry3d &T_world_base, double dt_s) {
    std::normal_distribution<double> n(0.0, 1.0);
    const double sigma_p = config_.position_sigma_m;
    const double sigma_r = DegToRad(config_.rotation_sigma_deg);
    // Stationary Gauss-Markov: x_k = a x_{k-1} + sqrt(1 - a^2) sigma w_k, started in steady state.
    const double a = started_ ? std::exp(-dt_s / config_.correlation_time_s) : 0.0;
    const double b = std::sqrt(1.0 - a * a);
    for (int i = 0; i < 3; ++i) {
        position_error_m_[i] = a * position_error_m_[i] + b * sigma_p * n(rng_);
        rotation_error_rad_[i] = a * rotation_error_rad_[i] + b * sigma_r * n(rng_);
    }
    started_ = true;
    Eigen::Isometry3d T = T_world_base;
    T.linear() = T_world_base.linear() * ExpSO3(rotation_error_rad_);
    T.translation() += position_error_m_;
    return T;
}

}  // namespace dorado::sim
