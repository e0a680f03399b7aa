#include "dorado/odometry/kinematic_model.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "dorado/core/lie.hpp"

namespace dorado::odometry {

KinematicModel::KinematicModel(const Extrinsics &extrinsics, const VehicleGeometry &geometry)
    : R_base_radar_(extrinsics.T_base_radar.linear()),
      p_base_radar_(extrinsics.T_base_radar.translation()),
      half_wheelbase_m_(geometry.half_wheelbase_m),
      model_noise_(geometry.model_noise),
      constrained_(geometry.model != VehicleModel::kUnconstrained) {
    if (!constrained_) {
        // No constraint: the Doppler gives the sensor velocity and nothing about the rotation.
        J_omega_.setZero();
        J_v_base_ = R_base_radar_;
        return;
    }
    const double s_x = p_base_radar_.x(), m = half_wheelbase_m_;
    if (!std::isfinite(s_x) || std::abs(s_x) < 1e-3)
        throw std::invalid_argument(
            "extrinsics.T_base_radar: the radar is on the rear axle (s_x = " + std::to_string(s_x) +
            " m): the yaw rate is unobservable from its velocity (eq. 5)");
    if (!std::isfinite(m) || std::abs(m - s_x) < 1e-3)
        throw std::invalid_argument(
            "vehicle.half_wheelbase_m: the radar is on the Y-ICR axis (m - s_x = " +
            std::to_string(m - s_x) + " m): the pitch rate is unobservable (eq. 5)");
    yaw_lever_m_ = s_x;
    BuildJacobians();
}

void KinematicModel::BuildJacobians() {
    const double s_x = p_base_radar_.x(), m = half_wheelbase_m_;
    // eq. (5) as a matrix on v_s (base frame): omega_y = v_sz / (m - s_x), omega_z = v_sy / s_x
    // (s_x the yaw lever: the radar's X position unless calibrated online, SetYawLever).
    Eigen::Matrix3d J_omega_vs = Eigen::Matrix3d::Zero();
    J_omega_vs(1, 2) = 1.0 / (m - s_x);
    J_omega_vs(2, 1) = 1.0 / yaw_lever_m_;
    J_omega_ = J_omega_vs * R_base_radar_;
    // v_base = v_s - omega x s = v_s + s x omega = (I + Hat(s) J_omega_vs) v_s.
    J_v_base_ = (Eigen::Matrix3d::Identity() + Hat(p_base_radar_) * J_omega_vs) * R_base_radar_;
}

void KinematicModel::SetYawLever(double s_x_m) {
    if (!constrained_) return;
    if (!std::isfinite(s_x_m) || std::abs(s_x_m) < 1e-3)
        throw std::invalid_argument("KinematicModel::SetYawLever: s_x = " + std::to_string(s_x_m) +
                                    " m leaves the yaw rate unobservable");
    yaw_lever_m_ = s_x_m;
    BuildJacobians();
}

VehicleMotion KinematicModel::Motion(const Eigen::Vector3d &v_radar,
                                     const Eigen::Matrix3d &cov_v_radar) const {
    VehicleMotion motion;
    motion.omega_base_radps = J_omega_ * v_radar;
    motion.v_base_mps = J_v_base_ * v_radar;
    // eq. (7): C_omega = J C_v J^T (exact: the model is linear in v).
    motion.cov_omega_base = J_omega_ * cov_v_radar * J_omega_.transpose();
    motion.cov_v_base = J_v_base_ * cov_v_radar * J_v_base_.transpose();
    motion.cov_v_omega_base = J_v_base_ * cov_v_radar * J_omega_.transpose();
    motion.cov_model = ModelCovariance(motion.v_base_mps, motion.omega_base_radps);
    return motion;
}

// With the violations kept, eq. (3) reads v_sy - omega_z s_x + omega_x s_z = dy (the rear axle's
// lateral velocity) and eq. (4) reads v_sz - omega_x s_y - omega_y (m - s_x) = dz (the Y-ICR
// point's vertical velocity). The model solves them with dy = dz = omega_x = 0, so its estimate
// minus the truth is
//   omega_x: -omega_x,   omega_y: (dz + omega_x s_y) / (m - s_x),   omega_z: (dy - omega_x s_z) /
//   s_x
// and, through v_base = v_s + s x omega (v_s is measured, not modelled), v_base: Hat(s) d_omega.
Eigen::Matrix<double, 6, 3> KinematicModel::ViolationJacobian() const {
    if (!constrained_) return Eigen::Matrix<double, 6, 3>::Zero();  // no constraint to violate
    const Eigen::Vector3d &s = p_base_radar_;
    const double m = half_wheelbase_m_;
    Eigen::Matrix3d G_omega;
    G_omega << 0.0, 0.0, -1.0,                        //
        0.0, 1.0 / (m - s.x()), s.y() / (m - s.x()),  //
        1.0 / yaw_lever_m_, 0.0, -s.z() / yaw_lever_m_;
    Eigen::Matrix<double, 6, 3> G;
    G << Hat(s) * G_omega, G_omega;
    return G;
}

Matrix6d KinematicModel::ModelCovariance(const Eigen::Vector3d &v_base,
                                         const Eigen::Vector3d &omega_base) const {
    if (!constrained_) return Matrix6d::Zero();
    const KinematicModelNoise &n = model_noise_;
    const double yaw_rate = std::abs(omega_base.z()), speed = std::abs(v_base.x());
    const double icr = n.sigma_icr_x_m * yaw_rate;
    const double slip = n.rear_slip_rad_per_mps2 * speed * speed * yaw_rate;
    const Eigen::Vector3d variance(
        icr * icr + slip * slip + n.sigma_lateral_mps * n.sigma_lateral_mps,
        n.sigma_vertical_mps * n.sigma_vertical_mps,
        n.sigma_roll_rate_radps * n.sigma_roll_rate_radps);
    const Eigen::Matrix<double, 6, 3> G = ViolationJacobian();
    return G * variance.asDiagonal() * G.transpose();
}

Twist KinematicModel::PlausibleTwist(const VehicleMotion &motion) const {
    Matrix6d covariance = motion.cov_model;
    covariance.topLeftCorner<3, 3>() += motion.cov_v_base;
    covariance.topRightCorner<3, 3>() += motion.cov_v_omega_base;
    covariance.bottomLeftCorner<3, 3>() += motion.cov_v_omega_base.transpose();
    covariance.bottomRightCorner<3, 3>() += motion.cov_omega_base;
    Vector6d x;
    x << motion.v_base_mps, motion.omega_base_radps;
    // The pseudo-measurement omega = 0 with covariance P: H = [0 I], S = H C H^T + P,
    // K = C H^T S^-1, x+ = x - K (H x), C+ = C - K H C.
    const Eigen::Matrix3d P =
        model_noise_.angular_rate_prior_sigma_radps.cwiseAbs2().asDiagonal().toDenseMatrix();
    const Eigen::Matrix3d S = covariance.bottomRightCorner<3, 3>() + P;
    const Eigen::Matrix<double, 6, 3> K =
        S.ldlt().solve(covariance.rightCols<3>().transpose()).transpose();
    x -= K * motion.omega_base_radps;
    covariance -= K * covariance.bottomRows<3>();
    Twist twist;
    twist.v_base_mps = x.head<3>();
    twist.omega_base_radps = x.tail<3>();
    twist.covariance = 0.5 * (covariance + covariance.transpose());
    return twist;
}

Eigen::Vector3d KinematicModel::BaseVelocity(const Eigen::Vector3d &v_radar,
                                             const Eigen::Vector3d &omega_base) const {
    return R_base_radar_ * v_radar - omega_base.cross(p_base_radar_);
}

}  // namespace dorado::odometry
