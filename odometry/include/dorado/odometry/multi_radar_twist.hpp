#pragma once
/// @file multi_radar_twist.hpp
/// The vehicle's planar twist (v_x, v_y, yaw rate) from several 2D radars' Doppler jointly
/// (Kellner et al., "Instantaneous ego-motion estimation using multiple Doppler radars", ICRA
/// 2014): each radar's static points constrain the base twist through that radar's mount, so
/// radars that look in different directions observe the yaw rate without a kinematic model (and
/// the lateral velocity the model sets to zero, which checks it).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "dorado/core/radar_scan.hpp"
#include "dorado/odometry/ego_velocity.hpp"

namespace dorado::odometry {

/// One radar's scan, its mount and its own ego-velocity result (whose static labels select the
/// points that join the joint fit; an invalid result contributes nothing).
struct RadarObservation {
    const RadarScan *scan_radar = nullptr;
    Eigen::Isometry3d T_base_radar = Eigen::Isometry3d::Identity();
    const EgoVelocityResult *ego = nullptr;
};

/// Why the joint fit gave no twist; the numbers are in PlanarTwist::failure_detail.
enum class PlanarTwistFailure {
    kNone,                ///< valid
    kNotEstimated,        ///< "not estimated": EstimatePlanarTwist did not run
    kTooFewRadars,        ///< "too few radars": < 2 with static points at distinct positions
    kTooFewPoints,        ///< "too few static points": < 4 over every radar
    kDegenerateGeometry,  ///< "degenerate geometry": the radars' directions miss the twist
    kNonFinite,           ///< "non-finite twist"
};

/// The cause in words, without numbers: "" for kNone, e.g. "too few radars".
[[nodiscard]] const char *ToString(PlanarTwistFailure failure);

struct PlanarTwist {
    PlanarTwistFailure failure = PlanarTwistFailure::kNotEstimated;  ///< kNone: valid
    std::string failure_detail;  ///< the numbers behind the failure (for messages)
    [[nodiscard]] bool valid() const { return failure == PlanarTwistFailure::kNone; }
    /// (v_x, v_y) of the base origin (rear-axle centre) in the base frame [m/s], yaw rate [rad/s].
    Eigen::Vector3d twist = Eigen::Vector3d::Zero();
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  ///< of twist: sigma^2 (A^T A)^-1
    double residual_sigma_mps = 0.0;  ///< RMS Doppler residual (the sigma above)
    int radars_used = 0;
    int points_used = 0;
};

/// For a static point i of radar k (direction d_i = (x, y) / r in the radar's plane, mount R_k,
/// position s_k in the base frame), eq. (1) and the rigid body give
///   -doppler_i = d_i . R_k^T (v_base + omega_z e_z x s_k)
///             = (R_k d_i)^T [1 0 -s_ky; 0 1 s_kx] (v_x, v_y, omega_z).
/// Least squares over every radar's static points (equal weights), covariance from the
/// residuals. Needs >= 2 radars with valid ego-velocities at distinct positions (else the yaw
/// rate is unobservable: PlanarTwistFailure::kTooFewRadars) and >= 4 points.
[[nodiscard]] PlanarTwist EstimatePlanarTwist(const std::vector<RadarObservation> &radars);

}  // namespace dorado::odometry
