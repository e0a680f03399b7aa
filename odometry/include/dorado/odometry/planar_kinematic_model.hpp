#pragma once
/// @file planar_kinematic_model.hpp
/// The paper's kinematic model (section III-B) in the plane, for a 2D radar: z, roll and pitch
/// are held, the rear axle has no lateral velocity (eq. 3), and the yaw rate follows (eq. 5's
/// omega_z).

#include <Eigen/Core>

#include "dorado/core/extrinsics.hpp"
#include "dorado/odometry/kinematic_model.hpp"

namespace dorado::odometry {

/// In the base frame (rear-axle centre, X forward, Y left), with s = (s_x, s_y) the radar's
/// position and v_s = R_base_radar v_radar its velocity (x, y):
///   v_s = v_base + omega_z e_z x s  =>  v_sx = v_bx - omega_z s_y,  v_sy = v_by + omega_z s_x.
/// The constraint v_by = 0 (eq. 3) gives
///   omega_z = v_sy / s_x,   v_bx = v_sx + omega_z s_y,   v_by = 0.
/// A lateral slip delta at the rear axle (the constraint broken) makes the estimate err by
/// d [v_bx, v_by, omega_z] / d delta = [s_y / s_x, -1, 1 / s_x]; its variance is
/// sigma_lateral^2 + (sigma_icr_x omega_z)^2 + (rear_slip v^2 omega_z)^2 (KinematicModelNoise).
class PlanarKinematicModel {
  public:
    /// Throws std::invalid_argument when |s_x| < 1 mm (the yaw rate is unobservable). With
    /// VehicleModel::kUnconstrained: no constraint, Motion() gives v_s as v_base and omega 0.
    PlanarKinematicModel(const Extrinsics &extrinsics, const VehicleGeometry &geometry);

    /// The base's motion from the radar velocity (its z ignored) and its covariance (eq. 7 in
    /// the plane: J C J^T); omega_x = omega_y = v_z = 0 with zero variance. The model's own
    /// error goes to VehicleMotion::cov_model.
    [[nodiscard]] VehicleMotion Motion(const Eigen::Vector3d &v_radar,
                                       const Eigen::Matrix3d &cov_v_radar) const;

    /// v_base = v_s - omega_z e_z x s with the yaw rate from elsewhere (a gyro's z), in the plane.
    [[nodiscard]] Eigen::Vector3d BaseVelocity(const Eigen::Vector3d &v_radar,
                                               double omega_z_radps) const;

    [[nodiscard]] bool constrained() const { return constrained_; }

  private:
    Eigen::Matrix2d R_base_radar_;  ///< the mount's rotation in the plane
    Eigen::Vector2d s_;             ///< the radar's position (x, y) in the base frame
    KinematicModelNoise noise_;
    bool constrained_ = true;
};

}  // namespace dorado::odometry
