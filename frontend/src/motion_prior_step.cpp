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

// The trapezoid needs the previous scan's twist at the interval's start, at the usual cadence:
// after a gap (a dropped scan or more: an interval over 1.5 times the previous one) that twist is
// stale and the scan's own is held, as the odometry does.
Twist RadarFrontEnd::State::IntervalTwist(const odometry::OdometryStep &step) const {
    const Twist twist = PriorTwist(step);
    if (config.prior_noise.doppler_integration != mapping::TwistIntegration::kTrapezoid ||
        !last_twist || !(last_dt_s > 0.0 && step.dt_s <= 1.5 * last_dt_s))
        return twist;
    return mapping::TrapezoidTwist(*last_twist, twist);
}

BuiltPrior RadarFrontEnd::State::BuildPrior(const odometry::OdometryStep &step, int64_t stamp_ns,
                                            double dt_s, bool twist_discontinuous) const {
    using mapping::PriorKind;
    const PriorKind kind = config.prior;
    BuiltPrior out;
    out.requested = kind;
    out.used = kind;
    if (scans_since_reset == 0) {  // the first scan defines the world
        out.prior.T_world_base = T_world_base_initial;
        out.prior.covariance = Matrix6d::Identity() * 1e-6;
        out.prior.kind = kind;  // unused: the first scan starts the map
        out.first_scan = true;
        return out;
    }
    const bool has_two = scans_since_reset >= 2 && last_dt_s > 0.0;
    const mapping::PriorNoiseConfig &noise = config.prior_noise;
    auto constvel = [&] {
        return has_two ? mapping::PriorConstantVelocity(T_world_base_prev2, T_world_base_prev,
                                                        last_dt_s, dt_s, noise)
                       : mapping::PriorFromPreviousPose(T_world_base_prev, noise);
    };
    std::optional<mapping::MotionPrior> built;
    PriorSubstitution why_not = PriorSubstitution::kNone;
    const std::vector<ImuSample> imu_samples = gyro_bias.Corrected(imu.samples());
    switch (kind) {
        case PriorKind::kNone:
            built = mapping::PriorFromPreviousPose(T_world_base_prev, noise);
            break;
        case PriorKind::kConstVel:
            built = constvel();
            break;
        case PriorKind::kImu: {
            std::optional<Eigen::Vector3d> v_world;  // unknown from one pose
            if (has_two)
                v_world = (T_world_base_prev.translation() - T_world_base_prev2.translation()) /
                          last_dt_s;
            built = mapping::PriorFromImu(T_world_base_prev, v_world, imu_samples, last_stamp_ns,
                                          stamp_ns, extrinsics.T_base_imu, noise);
            if (!built) why_not = PriorSubstitution::kNoImuSamples;
            break;
        }
        case PriorKind::kDoppler:
        case PriorKind::kImuDoppler:
            // The odometry's twist honours every odometry setting; a fallback twist (no valid
            // velocity, an implausible angular rate) is not a measurement: substitute.
            if (step.fallback_cause == odometry::FallbackCause::kInvalidVelocity) {
                why_not = PriorSubstitution::kInvalidDopplerVelocity;
            } else if (twist_discontinuous) {
                why_not = PriorSubstitution::kDiscontinuousTwist;
            } else if (step.fallback_cause == odometry::FallbackCause::kAngularRateLimit) {
                why_not = PriorSubstitution::kAngularRateLimit;
            } else if (step.fallback_cause == odometry::FallbackCause::kNoImuSamples) {
                why_not = PriorSubstitution::kNoImuSamples;
            } else if (kind == PriorKind::kDoppler) {
                built =
                    mapping::PriorFromDoppler(T_world_base_prev, IntervalTwist(step), dt_s, noise);
            } else {
                built = mapping::PriorFromImuAndDoppler(T_world_base_prev, IntervalTwist(step),
                                                        imu_samples, last_stamp_ns + 1, stamp_ns,
                                                        extrinsics.T_base_imu, dt_s, noise);
                if (!built) why_not = PriorSubstitution::kNoImuSamples;
            }
            // Not after a gap (the last motion is stale, as for the trapezoid) nor on a
            // stationary scan (the zero twist is exact).
            if (built && noise.doppler_with_constvel && has_two && dt_s <= 1.5 * last_dt_s &&
                !step.zero_velocity_update)
                built = mapping::FusePriors(*built, constvel());
            break;
    }
    if (!built) {
        out.used = PriorKind::kConstVel;
        out.substitution = why_not;
        if (why_not == PriorSubstitution::kInvalidDopplerVelocity)
            out.substitution_detail = step.ego.failure_detail;
        built = constvel();
    }
    out.prior = *built;
    return out;
}

}  // namespace dorado::frontend
