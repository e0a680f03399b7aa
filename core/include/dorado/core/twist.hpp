#pragma once
/// @file twist.hpp
/// The one 3-D twist type of dorado: the simulator's true velocity, the Doppler odometry's
/// estimate and the motion priors' input are all this.

#include <Eigen/Core>

#include "dorado/core/lie.hpp"

namespace dorado {

/// The velocity of the base frame (rear-axle centre), expressed in the base frame (a body twist:
/// over a short dt, T_world_base(t + dt) = T_world_base(t) ExpSE3([v_base; omega_base] dt)), with
/// the covariance of [v_base; omega_base] (the xi = [rho; phi] order of lie.hpp; zero when exact,
/// as the simulator's truth).
struct Twist {
    Eigen::Vector3d v_base_mps = Eigen::Vector3d::Zero();
    Eigen::Vector3d omega_base_radps = Eigen::Vector3d::Zero();
    Matrix6d covariance = Matrix6d::Zero();
};

}  // namespace dorado
