#pragma once
/// @file pose_covariance.hpp
/// The dead-reckoned pose's covariance, by first-order propagation of the integrated twist's:
/// with the pose error as a world-frame perturbation T = Exp(xi) T_hat, xi = [rho; phi] (the
/// order of nav_msgs/Odometry's pose covariance: x, y, z, rotation about x, y, z), a step
/// T_k+1 = T_k Exp(tau dt) with tau ~ N(tau_hat, C) adds dt^2 Ad(T_k+1) C Ad(T_k+1)^T.

#include <Eigen/Geometry>

#include "dorado/core/lie.hpp"

namespace dorado::ros_node {

class PoseCovariance {
  public:
    /// Starts over (the initial pose is known exactly).
    void Reset() { covariance_.setZero(); }

    /// Adds one integration step of the twist [v; omega] (base frame, covariance C_twist) over
    /// dt_s, ending at T_world_base.
    void Step(const Eigen::Isometry3d &T_world_base, const Matrix6d &C_twist, double dt_s) {
        Matrix6d Ad = Matrix6d::Zero();
        const Eigen::Matrix3d R = T_world_base.linear();
        Ad.topLeftCorner<3, 3>() = R;
        Ad.topRightCorner<3, 3>() = Hat(T_world_base.translation()) * R;
        Ad.bottomRightCorner<3, 3>() = R;
        covariance_ += dt_s * dt_s * Ad * C_twist * Ad.transpose();
    }

    /// Also the covariance of T_world_base * T_base_child for a constant offset T_base_child (a
    /// world-frame perturbation does not change under a right multiplication).
    [[nodiscard]] const Matrix6d &covariance() const { return covariance_; }

  private:
    Matrix6d covariance_ = Matrix6d::Zero();
};

}  // namespace dorado::ros_node
