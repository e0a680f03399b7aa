#pragma once
/// @file kinematic_model.hpp
/// Vehicle motion from the radar velocity through the paper's kinematic model (section III-B,
/// eq. 3-5, covariance eq. 7).

#include <Eigen/Core>

#include "dorado/core/extrinsics.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/core/twist.hpp"

namespace dorado::odometry {

/// Linear and angular velocity of the base frame (rear-axle centre), expressed in the base frame.
struct VehicleMotion {
    Eigen::Vector3d v_base_mps = Eigen::Vector3d::Zero();
    Eigen::Vector3d omega_base_radps = Eigen::Vector3d::Zero();
    Eigen::Matrix3d cov_v_base = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d cov_omega_base = Eigen::Matrix3d::Zero();
    /// Cross-covariance of v_base and omega_base (eq. 7's propagation: both come from v_radar).
    Eigen::Matrix3d cov_v_omega_base = Eigen::Matrix3d::Zero();
    /// Covariance of the model's own error (the vehicle breaking the constraints, see
    /// KinematicModelNoise), of [v_base; omega_base]: add it to the blocks above for an honest
    /// total. Zero when the geometry's model_noise is zero.
    Matrix6d cov_model = Matrix6d::Zero();
};

/// The paper's kinematic constraints, in the base frame (X forward, Y left, Z up, origin at the
/// rear-axle centre): points on the Z-ICR axis (the rear axle, x = 0) have no Y velocity, points on
/// the Y-ICR axis (x = m, m = half wheelbase) have no Z velocity, and there is no roll (omega_x =
/// 0).
///
/// Derivation (rigid body, eq. 3: v_p = v_s + omega x (p - s), s = radar position in base):
///  - p_a = (0, s_y, 0):  p_a - s = (-s_x, 0, -s_z),
///    v_ay = v_sy + omega_z (-s_x) - omega_x (-s_z) = v_sy - omega_z s_x + omega_x s_z = 0   (eq.
///    3)
///  - p_b = (m, 0, s_z):  p_b - s = (m - s_x, -s_y, 0),
///    v_bz = v_sz + omega_x (-s_y) - omega_y (m - s_x) = v_sz - omega_x s_y - omega_y (m - s_x) = 0
///                                                                                         (eq. 4)
///  - with omega_x = 0:  omega = (0, v_sz / (m - s_x), v_sy / s_x)                          (eq. 5)
/// Signs check: a radar ahead of the rear axle (s_x > 0) moving left (v_sy > 0) means a left turn,
/// omega_z > 0 (counter-clockwise seen from above); a radar behind the middle (s_x < m) moving up
/// means the nose pitches down (omega_y > 0 about the left-pointing Y axis), as on a crest.
/// The paper's signs in eq. 5 agree with this derivation.
/// The base velocity is v_base = v_s - omega x s (eq. 3 with p = base origin).
class KinematicModel {
  public:
    /// Throws std::invalid_argument when s_x = 0 (yaw unobservable) or s_x = m (pitch
    /// unobservable) to within 1 mm. With VehicleModel::kUnconstrained there is no constraint and
    /// no check: Motion() then gives the sensor velocity R_base_radar v_radar as v_base, a zero
    /// omega and no model noise (the rotation must come from a gyro, see BaseVelocity).
    KinematicModel(const Extrinsics &extrinsics, const VehicleGeometry &geometry);

    /// False for VehicleModel::kUnconstrained: the Doppler says nothing about the rotation.
    [[nodiscard]] bool constrained() const { return constrained_; }

    /// Vehicle motion from the radar velocity in the radar frame and its covariance. Covariances
    /// by first-order propagation (eq. 7): J C_v J^T with J the exact (linear) Jacobian; the
    /// model's own error goes to VehicleMotion::cov_model.
    [[nodiscard]] VehicleMotion Motion(const Eigen::Vector3d &v_radar,
                                       const Eigen::Matrix3d &cov_v_radar) const;

    /// The twist to use as a motion prior: eq. (5)'s estimate with the total covariance (eq. 7 +
    /// the model's own error), updated (Kalman, on [v_base; omega]) with the prior that the
    /// angular rates are about zero with KinematicModelNoise::angular_rate_prior_sigma_radps. Where
    /// eq. (5) is well conditioned this moves a rate by a few percent of itself at most; where it
    /// is not (a radar near an ICR axis) it keeps the poorly observed rate, and the base velocity
    /// that depends on it through the lever arm, from taking absurd values.
    [[nodiscard]] Twist PlausibleTwist(const VehicleMotion &motion) const;

    /// d v_base / d v_radar (constant: the model is linear in v_radar).
    [[nodiscard]] const Eigen::Matrix3d &VelocityJacobian() const { return J_v_base_; }

    /// d v_s / d v_radar = R_base_radar.
    [[nodiscard]] const Eigen::Matrix3d &SensorVelocityJacobian() const { return R_base_radar_; }

    /// Base velocity when omega comes from elsewhere (a gyro): v_base = v_s - omega x s.
    [[nodiscard]] Eigen::Vector3d BaseVelocity(const Eigen::Vector3d &v_radar,
                                               const Eigen::Vector3d &omega_base) const;

    [[nodiscard]] const Eigen::Vector3d &p_base_radar() const { return p_base_radar_; }

    /// The lever of eq. (5)'s yaw rate, omega_z = v_sy / s_x: the radar's X position unless set.
    [[nodiscard]] double yaw_lever_m() const { return yaw_lever_m_; }
    /// Replaces the yaw lever (an online calibration of the Z-ICR offset, yaw_calibration.hpp):
    /// omega_z = v_sy / s_x_m from now on, and the base velocity through the physical lever arm
    /// p_base_radar (so the rear axle gets the lateral velocity of an ICR ahead of it). Throws
    /// std::invalid_argument for |s_x_m| < 1 mm; no effect on an unconstrained model.
    void SetYawLever(double s_x_m);

    /// How the estimate errs when the constraints are broken: d [v_base; omega_base] (estimate
    /// minus truth) / d [lateral velocity at the rear axle; vertical velocity at the Y-ICR point;
    /// roll rate]. From eq. (3) and (4) with the violations kept (derivation in the .cpp).
    [[nodiscard]] Eigen::Matrix<double, 6, 3> ViolationJacobian() const;

  private:
    void BuildJacobians();
    [[nodiscard]] Matrix6d ModelCovariance(const Eigen::Vector3d &v_base,
                                           const Eigen::Vector3d &omega_base) const;

    Eigen::Matrix3d R_base_radar_;
    Eigen::Vector3d p_base_radar_;  ///< s, the radar position in the base frame
    double half_wheelbase_m_;
    double yaw_lever_m_ = 0.0;  ///< eq. (5)'s s_x for the yaw rate (SetYawLever)
    KinematicModelNoise model_noise_;
    bool constrained_ = true;
    Eigen::Matrix3d J_omega_;   ///< omega_base = J_omega_ v_radar
    Eigen::Matrix3d J_v_base_;  ///< v_base = J_v_base_ v_radar
};

}  // namespace dorado::odometry
