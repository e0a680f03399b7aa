// Step 2 of RadarFrontEnd::Process: the motion prior from the odometry's twist, the IMU or the
// previous poses, and the continuity test of the Doppler twist (front_end_state.hpp).
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "front_end_state.hpp"

namespace dorado::frontend {

Twist PriorTwist(const odometry::OdometryStep &step) {
    return {step.v_base_used_mps, step.omega_base_used_radps, step.covariance_used};
}

// The change within the twists' covariances plus the constvel prior's accelerations over the time
// between them (chi^2 at 99.9 % per 3-dof block; the v block alone with the gyro's rotation,
// imu+doppler). A RANSAC that locked onto a crowd moving with the vehicle jumps by metres per
// second in one scan. After a second of refusals the twist is taken again (the vehicle did
// change).
bool RadarFrontEnd::State::TwistIsContinuous(const odometry::OdometryStep &step) {
    const Twist twist = PriorTwist(step);
    const bool fresh = !last_plausible_twist || since_plausible_s + step.dt_s > 1.0;
    if (!fresh) {
        const Twist &last = *last_plausible_twist;
        const double dt = since_plausible_s + step.dt_s;
        const mapping::PriorNoiseConfig &noise = config.prior_noise;
        // One block's change against both twists' covariances plus an acceleration over dt.
        const auto chi2_of = [dt](const Eigen::Vector3d &d, const Eigen::Matrix3d &C,
                                  double sigma_accel) {
            const Eigen::Matrix3d S =
                C + Eigen::Matrix3d::Identity() * std::pow(sigma_accel * dt, 2);
            return d.dot(S.ldlt().solve(d));
        };
        const Matrix6d C = twist.covariance + last.covariance;
        double chi2 = chi2_of(twist.v_base_mps - last.v_base_mps, C.topLeftCorner<3, 3>(),
                              noise.constvel_sigma_accel_mps2);
        if (config.prior == mapping::PriorKind::kDoppler)
            chi2 = std::max(chi2, chi2_of(twist.omega_base_radps - last.omega_base_radps,
                                          C.bottomRightCorner<3, 3>(),
                                          noise.constvel_sigma_angular_accel_radps2));
        constexpr double kGate = 16.27;  // chi^2(3) at 99.9 %, each block
        if (!(chi2 <= kGate)) {
            since_plausible_s += step.dt_s;
            return false;
        }
    }
    last_plausible_twist = twist;
    since_plausible_s = 0.0;
    return true;
}

BuiltPrior RadarFrontEnd::State::BuildPrior(const odometry::OdometryStep &step, int64_t stamp_ns,
                                            double dt_s, bool twist_discontinuous) const {
    PriorInputs in;
    in.kind = config.prior;
    in.poses = scans_since_reset;
    in.T_world_base_first = T_world_base_initial;
    in.T_world_base_prev = T_world_base_prev;
    in.T_world_base_prev2 = T_world_base_prev2;
    in.last_stamp_ns = last_stamp_ns;
    in.stamp_ns = stamp_ns;
    in.last_dt_s = last_dt_s;
    in.dt_s = dt_s;
    // The odometry's twist honours every odometry setting; a fallback twist (no valid velocity,
    // an implausible angular rate) is not a measurement.
    using odometry::FallbackCause;
    if (step.fallback_cause == FallbackCause::kInvalidVelocity) {
        in.refused = PriorSubstitution::kInvalidDopplerVelocity;
        in.refused_detail = step.ego.failure_detail;
    } else if (twist_discontinuous) {
        in.refused = PriorSubstitution::kDiscontinuousTwist;
    } else if (step.fallback_cause == FallbackCause::kAngularRateLimit) {
        in.refused = PriorSubstitution::kAngularRateLimit;
    } else if (step.fallback_cause == FallbackCause::kNoImuSamples) {
        in.refused = PriorSubstitution::kNoImuSamples;
    } else {
        in.twist = PriorTwist(step);
    }
    in.last_twist = last_twist;
    in.imu_samples = gyro_bias.Corrected(imu.samples());
    in.T_base_imu = extrinsics.T_base_imu;
    in.constvel_fusion_allowed = !step.zero_velocity_update;
    return BuildMotionPrior(in, config.prior_noise);
}

}  // namespace dorado::frontend
