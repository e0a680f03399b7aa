#pragma once
/// @file vehicle_velocity_prior.hpp
/// The vehicle constraint on a ground vehicle's ego-velocity (core VehicleVelocityPrior): the
/// base (rear-axle centre) has about no lateral and no vertical velocity in its own frame, so
/// weak elevation cannot make a car climb.

#include <Eigen/Core>

#include "dorado/core/extrinsics.hpp"

namespace dorado::odometry {

/// The radar velocity and its covariance after the prior.
struct ConstrainedVelocity {
    Eigen::Vector3d v_radar_mps = Eigen::Vector3d::Zero();
    Eigen::Matrix3d cov_v_radar = Eigen::Matrix3d::Zero();
};

/// The base velocity is affine in the radar velocity, v_base = A v_radar + c: A = the kinematic
/// model's d v_base / d v_radar and c = 0 when the rotation comes from the same v_radar (eq. 5);
/// A = R_base_radar and c = -omega x s when the rotation comes from a gyro. Rows Y and Z of it
/// are pseudo-measurements v_base,y = 0 and v_base,z = 0 with variances sigma_lateral^2 and
/// sigma_vertical^2; the Kalman update on v_radar (H = A.bottomRows<2>(), S = H C H^T + P,
/// K = C H^T S^-1):
///   v+ = v - K (H v + c_yz),   C+ = C - K H C.
/// A row of H that is zero (the Ackermann model already holds v_base,y = 0) leaves v unchanged.
/// With prior.enabled false, returns v and C unchanged.
[[nodiscard]] ConstrainedVelocity ApplyVehicleVelocityPrior(const VehicleVelocityPrior &prior,
                                                            const Eigen::Matrix3d &A,
                                                            const Eigen::Vector3d &c,
                                                            const Eigen::Vector3d &v_radar,
                                                            const Eigen::Matrix3d &cov_v_radar);

}  // namespace dorado::odometry
