// The paper's kinematic model in the plane (derivation in planar_kinematic_model.hpp).
#include "dorado/odometry/planar_kinematic_model.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "dorado/core/lie.hpp"

namespace dorado::odometry {

PlanarKinematicModel::PlanarKinematicModel(const Extrinsics &extrinsics,
                                           const VehicleGeometry &geometry)
    : noise_(geometry.model_noise), constrained_(geometry.model != VehicleModel::kUnconstrained) {
    // The radar's plane is the base's: only the mount's yaw and (x, y) matter.
    const Eigen::Matrix3d R = extrinsics.T_base_radar.linear();
    const double yaw = std::atan2(R(1, 0), R(0, 0));
    R_base_radar_ << std::cos(yaw), -std::sin(yaw), std::sin(yaw), std::cos(yaw);
    s_ = extrinsics.T_base_radar.translation().head<2>();
    if (constrained_ && std::abs(s_.x()) < 1e-3)
        throw std::invalid_argument(
            "extrinsics.T_base_radar: a 2D radar on the rear axle (x = " + std::to_string(s_.x()) +
            " m) cannot observe the yaw rate through the vehicle model (eq. 5: omega_z = v_sy / "
            "s_x)");
}

VehicleMotion PlanarKinematicModel::Motion(const Eigen::Vector3d &v_radar,
                                           const Eigen::Matrix3d &cov_v_radar) const {
    VehicleMotion motion;
    const Eigen::Vector2d v_s = R_base_radar_ * v_radar.head<2>();
    const Eigen::Matrix2d cov_s =
        R_base_radar_ * cov_v_radar.topLeftCorner<2, 2>() * R_base_radar_.transpose();
    if (!constrained_) {
        motion.v_base_mps << v_s, 0.0;
        motion.cov_v_base.topLeftCorner<2, 2>() = cov_s;
        return motion;
    }
    const double omega_z = v_s.y() / s_.x();
    const double v_bx = v_s.x() + omega_z * s_.y();
    motion.v_base_mps = {v_bx, 0.0, 0.0};
    motion.omega_base_radps = {0.0, 0.0, omega_z};
    // d [v_bx, omega_z] / d v_s (eq. 7 in the plane).
    Eigen::Matrix2d J;
    J << 1.0, s_.y() / s_.x(), 0.0, 1.0 / s_.x();
    const Eigen::Matrix2d C = J * cov_s * J.transpose();
    motion.cov_v_base(0, 0) = C(0, 0);
    motion.cov_omega_base(2, 2) = C(1, 1);
    motion.cov_v_omega_base(0, 2) = C(0, 1);
    // The model's own error: a lateral slip delta at the rear axle (see the header).
    const double v2 = v_bx * v_bx;
    const double sigma2 = noise_.sigma_lateral_mps * noise_.sigma_lateral_mps +
                          std::pow(noise_.sigma_icr_x_m * omega_z, 2) +
                          std::pow(noise_.rear_slip_rad_per_mps2 * v2 * omega_z, 2);
    Vector6d dx = Vector6d::Zero();
    dx(0) = s_.y() / s_.x();
    dx(1) = -1.0;
    dx(5) = 1.0 / s_.x();
    motion.cov_model = sigma2 * dx * dx.transpose();
    return motion;
}

Eigen::Vector3d PlanarKinematicModel::BaseVelocity(const Eigen::Vector3d &v_radar,
                                                   double omega_z_radps) const {
    const Eigen::Vector2d v_s = R_base_radar_ * v_radar.head<2>();
    // v_base = v_s - omega_z e_z x s, e_z x s = (-s_y, s_x).
    return {v_s.x() + omega_z_radps * s_.y(), v_s.y() - omega_z_radps * s_.x(), 0.0};
}

}  // namespace dorado::odometry
