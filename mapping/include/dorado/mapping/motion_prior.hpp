#pragma once
/// @file motion_prior.hpp
/// Motion priors for scan-to-map registration (paper section IV-C): where the vehicle should be at
/// the new scan, and how sure we are. Each builder is a free function on plain data, so the mapper
/// does not depend on where the motion came from (Doppler odometry, IMU, previous poses).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "dorado/core/imu.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/core/twist.hpp"

namespace dorado::mapping {

/// The mapper's motion priors (paper section IV-C, Fig. 6-7); the one spelling of each is
/// ToString's.
enum class PriorKind {
    kNone,        ///< "none": the previous pose, a wide covariance (the paper's failing base case)
    kConstVel,    ///< "constvel": the last relative motion repeated (kiss-icp)
    kImu,         ///< "imu": gyro rotation and accelerometer double integration
    kDoppler,     ///< "doppler": the Doppler odometry's twist (the paper)
    kImuDoppler,  ///< "imu+doppler": gyro rotation, Doppler translation (the paper's I+D)
};

/// Every kind, in the order above.
inline constexpr PriorKind kAllPriorKinds[] = {PriorKind::kNone, PriorKind::kConstVel,
                                               PriorKind::kImu, PriorKind::kDoppler,
                                               PriorKind::kImuDoppler};
/// "none" | "constvel" | "imu" | "doppler" | "imu+doppler".
[[nodiscard]] const char *ToString(PriorKind kind);
/// The inverse of ToString; throws std::invalid_argument listing the choices otherwise.
[[nodiscard]] PriorKind ParsePriorKind(const std::string &name);
/// Whether the prior needs gyro (and accelerometer) samples.
[[nodiscard]] inline bool NeedsImu(PriorKind kind) {
    return kind == PriorKind::kImu || kind == PriorKind::kImuDoppler;
}
/// Whether the prior needs (and then carries) the Doppler ego-velocity.
[[nodiscard]] inline bool NeedsDoppler(PriorKind kind) {
    return kind == PriorKind::kDoppler || kind == PriorKind::kImuDoppler;
}

/// A predicted pose of the base frame in the world, with the covariance of its error.
///
/// The error is the tangent perturbation xi = [rho; phi] (translation first, metres and radians)
/// on the right: T_true = T_world_base * ExpSE3(xi), i.e. expressed in the predicted base frame.
struct MotionPrior {
    Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
    Matrix6d covariance = Matrix6d::Identity();
    /// What it was built from. With NeedsDoppler(kind) the prior carries the Doppler
    /// ego-velocity: the mapper's Doppler residuals would count the same points a second time.
    PriorKind kind = PriorKind::kNone;
};

/// How the `doppler` and `imu+doppler` priors turn the scans' twists into the interval's motion:
/// - kEndpoint: this scan's twist held over the interval (the paper's and `dorado odometry`'s
///   dead reckoning): errs by about a dt^2 / 2 under an acceleration a;
/// - kTrapezoid: the mean of the previous scan's and this scan's twists (TrapezoidTwist), the
///   interval's mean velocity to second order. After a gap (an interval over 1.5 times the
///   previous one) the front end holds the scan's own twist: the previous one is stale.
enum class TwistIntegration { kEndpoint, kTrapezoid };
/// "endpoint" | "trapezoid".
[[nodiscard]] const char *ToString(TwistIntegration integration);

/// The mean twist of an interval by the trapezoid rule: (start + end) / 2, covariance
/// (C_start + C_end) / 2. Not / 4, although the two scans' estimates are independent: consecutive
/// intervals share a scan, so their errors are correlated and n intervals sum to about n times
/// this covariance, as with the end's twist alone (the fusion's gain depends on that sum; with
/// / 4 the map's rotation drift per second grew 16 %, benchmark_prior_integration.yaml).
[[nodiscard]] Twist TrapezoidTwist(const Twist &at_start, const Twist &at_end);

/// Noise levels of the priors. Defaults are for a car-like vehicle at 10-20 Hz; see
/// configs/mapper.yaml.
struct PriorNoiseConfig {
    /// `none`: how far the vehicle may have gone since the previous scan (1 sigma).
    double none_sigma_translation_m = 2.0;
    double none_sigma_rotation_rad = 0.3;
    /// `constvel`: unmodelled linear / angular acceleration (1 sigma).
    double constvel_sigma_accel_mps2 = 3.0;
    double constvel_sigma_angular_accel_radps2 = 1.5;
    /// `imu`: gyro and accelerometer white noise, and the uncertainty of the velocity the
    /// accelerometer integration starts from (taken from the mapper's previous motion).
    double imu_gyro_sigma_radps = 0.01;
    double imu_accel_sigma_mps2 = 0.2;
    double imu_velocity_sigma_mps = 0.3;
    Eigen::Vector3d gravity_world_mps2 = Eigen::Vector3d(0.0, 0.0, -9.81);
    /// `doppler`: floors added to the twist's covariances (unmodelled biases, and a positive
    /// definite prior even from a perfect scan). The kinematic model's own error (roll rate,
    /// slip, bounce) comes with the twist (odometry::VehicleMotion::cov_model), not from here.
    double doppler_min_sigma_v_mps = 0.02;
    Eigen::Vector3d doppler_min_sigma_omega_radps = Eigen::Vector3d(0.005, 0.005, 0.005);
    /// `doppler`, `imu+doppler`: the interval's twist (TwistIntegration). The floors above are
    /// added after it (an unmodelled bias does not average out between two scans).
    TwistIntegration doppler_integration = TwistIntegration::kTrapezoid;
    /// `doppler`, `imu+doppler`: fuse the Doppler prior with the constvel prediction from the
    /// last two poses (FusePriors), so that a twist from a few points (its covariance wide) leans
    /// on the vehicle's last motion instead of being taken whole when the registration falls back.
    /// Not after a gap (an interval over 1.5 times the previous one) nor on a stationary scan.
    /// Off by default: it won on the built-in world and xsim seeds 100-102, lost on seeds 103-104
    /// (configs/mapper.yaml).
    bool doppler_with_constvel = false;

    /// Throws std::invalid_argument naming the first bad key.
    void Validate() const;
};

/// `none` (the paper's failing base case): the previous pose, with a wide covariance.
[[nodiscard]] MotionPrior PriorFromPreviousPose(const Eigen::Isometry3d &T_world_base_prev,
                                                const PriorNoiseConfig &noise);

/// `constvel` (kiss-icp): repeat the last relative motion, scaled to this interval.
/// dt_prev_s is the interval between the two previous poses, dt_s the interval to predict.
[[nodiscard]] MotionPrior PriorConstantVelocity(const Eigen::Isometry3d &T_world_base_prevprev,
                                                const Eigen::Isometry3d &T_world_base_prev,
                                                double dt_prev_s, double dt_s,
                                                const PriorNoiseConfig &noise);

/// `imu`: gyro rotation and accelerometer double integration over (t0_ns, t1_ns], starting from
/// the previous pose and the world velocity v_world_prev_mps. Empty when no sample falls in the
/// interval. The lever arm of the IMU is neglected in the acceleration (a few mm/s^2 on a car).
/// No start velocity (the first interval: one pose gives none) integrates from rest with the
/// translation spread of `none`: an accelerometer alone cannot say how fast the vehicle already
/// goes, and a prior that claimed rest would refuse every registration of a moving start.
[[nodiscard]] std::optional<MotionPrior> PriorFromImu(
    const Eigen::Isometry3d &T_world_base_prev,
    const std::optional<Eigen::Vector3d> &v_world_prev_mps, const std::vector<ImuSample> &samples,
    int64_t t0_ns, int64_t t1_ns, const Eigen::Isometry3d &T_base_imu,
    const PriorNoiseConfig &noise);

/// `doppler` (the paper): constant base twist from the Doppler odometry (as its kinematic model
/// gives it, paper eq. 6-7 and 9) over dt_s, T = T_world_base_prev * ExpSE3([v; omega] dt),
/// covariance blockdiag(C_v, C_omega) dt^2 with floors (the twist's diagonal blocks: the prior
/// drops the v-omega cross-covariance).
[[nodiscard]] MotionPrior PriorFromDoppler(const Eigen::Isometry3d &T_world_base_prev,
                                           const Twist &twist, double dt_s,
                                           const PriorNoiseConfig &noise);

/// `imu+doppler` (the paper's I+D): rotation rate from the mean gyro over (t0_ns, t1_ns], rotated
/// into the base frame; translation velocity from the Doppler odometry. Empty without IMU samples.
[[nodiscard]] std::optional<MotionPrior> PriorFromImuAndDoppler(
    const Eigen::Isometry3d &T_world_base_prev, const Twist &twist,
    const std::vector<ImuSample> &samples, int64_t t0_ns, int64_t t1_ns,
    const Eigen::Isometry3d &T_base_imu, double dt_s, const PriorNoiseConfig &noise);

/// Two independent predictions of the same pose fused by information: the mean moved from a's
/// towards b's (in a's tangent space) by C C_b^-1 LogSE3(T_a^-1 T_b), with covariance C = (C_a^-1 +
/// C_b^-1)^-1; a's kind.
[[nodiscard]] MotionPrior FusePriors(const MotionPrior &a, const MotionPrior &b);

/// Squared Mahalanobis distance of T_world_base from the prior: xi^T C^-1 xi with
/// xi = LogSE3(prior.T_world_base^-1 * T_world_base).
[[nodiscard]] double PriorMahalanobisSquared(const MotionPrior &prior,
                                             const Eigen::Isometry3d &T_world_base);

}  // namespace dorado::mapping
