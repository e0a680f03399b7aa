#pragma once
/// @file extrinsics.hpp
/// Where the sensors sit on the vehicle, and the vehicle's geometry.
///
/// The base frame is the paper's (section III-B): origin at the centre of the rear axle (on the
/// Z-ICR axis), X forward towards the front axle, Y left along the rear axle, Z up.

#include <Eigen/Geometry>
#include <limits>

namespace dorado {

struct Extrinsics {
    Eigen::Isometry3d T_base_radar =
        Eigen::Isometry3d::Identity();  ///< x_base = T_base_radar x_radar
    Eigen::Isometry3d T_base_imu = Eigen::Isometry3d::Identity();  ///< x_base = T_base_imu x_imu
};

/// How far a real vehicle breaks the kinematic model's three constraints (paper section III-B):
/// the rear axle slips sideways, the Y-ICR point moves vertically (suspension, bumps) and the body
/// rolls. Each violation is a 1-sigma size; together they give the model's own error covariance,
/// which the paper's eq. (7) (estimator noise only) leaves out.
struct KinematicModelNoise {
    /// Uncertainty of where the Z-ICR really is along X [m]: a lateral velocity
    /// sigma_icr_x_m * |omega_z| at the rear axle (skid-steer vehicles turn about a point that
    /// wanders with load and ground; for a car with a rigid rear axle it is small).
    double sigma_icr_x_m = 0.1;
    /// Sideslip angle of the rear axle per lateral acceleration [rad per m/s^2]: a lateral
    /// velocity rear_slip_rad_per_mps2 * v^2 * |omega_z| (tyres slip in fast turns).
    double rear_slip_rad_per_mps2 = 0.005;
    /// Lateral velocity of the rear axle from vibration and rough ground, always present [m/s].
    double sigma_lateral_mps = 0.02;
    /// Vertical velocity of the Y-ICR point (suspension, bumps) [m/s].
    double sigma_vertical_mps = 0.05;
    /// The roll rate the model sets to zero [rad/s].
    double sigma_roll_rate_radps = 0.05;
    /// Spread of the vehicle's angular rates about zero (roll, pitch, yaw) [rad/s], 1 sigma: a
    /// prior, not a violation. It matters only where eq. (5) is ill-conditioned (a radar close to
    /// the Y-ICR or Z-ICR axis, e.g. a side mount near mid-wheelbase, gives pitch rates of tens of
    /// deg/s of noise); KinematicModel::PlausibleTwist combines it with the estimate. A ground
    /// vehicle's body rolls and pitches at a few deg/s (0.2 rad/s = 11 deg/s is a kerb taken
    /// fast); it yaws at up to ~1 rad/s. Measured on both simulated worlds against 0.5 for roll
    /// and pitch: docs/robust_mapping.md.
    Eigen::Vector3d angular_rate_prior_sigma_radps{0.2, 0.2, 1.5};
};

/// The vehicle constraint on the ego-velocity of a ground vehicle (the dataset's
/// `vehicle.velocity_prior`): the base (rear-axle centre) moves along its own X, so its lateral
/// and vertical velocities are about zero with these 1-sigma spreads. A pseudo-measurement on the
/// radar velocity before the kinematic model (odometry/vehicle_velocity_prior.hpp): where the scan
/// observes a direction weakly (a real radar's elevation), the prior holds it; where the scan
/// observes it well, the scan wins. Off for hand-held and aerial platforms (refused with
/// vehicle.model unconstrained).
struct VehicleVelocityPrior {
    bool enabled = false;
    double sigma_lateral_mps = 0.1;
    double sigma_vertical_mps = 0.1;
};

/// Which kinematic constraint the platform obeys (the dataset's `vehicle.model`).
enum class VehicleModel {
    /// The paper's model (section III-B): Z-ICR on the rear axle (x = 0), Y-ICR at x =
    /// half_wheelbase_m, no roll. The Doppler alone gives the rotation (eq. 5).
    kAckermann,
    /// The same constraints with both ICR axes on one line (half_wheelbase_m = 0): a skid-steer
    /// base
    /// (the paper's Husky).
    kSkidSteer,
    /// No kinematic constraint (hand-held, drone, legged robot): the Doppler gives the velocity
    /// only; the rotation must come from a gyro (imu+doppler), Doppler-only rotation is refused.
    kUnconstrained,
};

/// "ackermann" | "skid_steer" | "unconstrained".
[[nodiscard]] inline const char *ToString(VehicleModel model) {
    switch (model) {
        case VehicleModel::kAckermann:
            return "ackermann";
        case VehicleModel::kSkidSteer:
            return "skid_steer";
        case VehicleModel::kUnconstrained:
            return "unconstrained";
    }
    return "?";
}

struct VehicleGeometry {
    /// Half the distance between the two axles [m] (the paper's m): the Y-ICR axis is at x = m.
    double half_wheelbase_m = 0.256;
    KinematicModelNoise model_noise;
    /// The platform's kinematic constraint; kUnconstrained ignores half_wheelbase_m and
    /// model_noise. Last, so that {m, noise} aggregates keep their meaning.
    VehicleModel model = VehicleModel::kAckermann;
    /// Height of the base origin (rear-axle centre) above the road [m], about the wheel radius:
    /// where the ground-plane attitude looks for the road (z_base = -base_height_m). NaN =
    /// unknown (the dataset's vehicle.base_height_m absent): no ground-plane attitude.
    double base_height_m = std::numeric_limits<double>::quiet_NaN();
    VehicleVelocityPrior velocity_prior;
};

}  // namespace dorado
