#pragma once
// Internal to dorado_odometry: eq. (2)'s weights, each point's inlier gate and the gate's
// variance factor, shared by the 3-D (ego_velocity.cpp) and the planar (planar_ego_velocity.cpp)
// estimators.
#include <Eigen/Core>

#include "dorado/odometry/ego_velocity.hpp"

namespace dorado::odometry::internal {

/// eq. (2) weights from power, normalised to a largest weight of 1 (`w` holds each used point's
/// power [dB] on entry), and each point's squared inlier gate, which follows its Doppler noise.
/// Without power (config.use_power off, or `has_power` false) every weight is 1.
void AssignWeightsAndGates(const EgoVelocityConfig &config, bool has_power,
                           Eigen::Ref<Eigen::VectorXd> w, Eigen::Ref<Eigen::VectorXd> gate2);

/// Inflation of the covariance of an estimate refit on the points inside a hard +-k sigma gate,
/// whatever the number of unknowns: (P / (P - 2 k phi(k)))^2 with P = P(|z| < k).
[[nodiscard]] double GateConsistencyFactor(double k);

}  // namespace dorado::odometry::internal
