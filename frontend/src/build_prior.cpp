// The motion prior of one scan for both front ends (built_prior.hpp).
#include <optional>

#include "built_prior.hpp"

namespace dorado::frontend {

BuiltPrior BuildMotionPrior(const PriorInputs &in, const mapping::PriorNoiseConfig &noise) {
    using mapping::PriorKind;
    BuiltPrior out;
    out.requested = in.kind;
    out.used = in.kind;
    if (in.poses == 0) {  // the first scan defines the world
        out.prior.T_world_base = in.T_world_base_first;
        out.prior.covariance = Matrix6d::Identity() * 1e-6;
        out.prior.kind = in.kind;  // unused: the first scan starts the map
        out.first_scan = true;
        return out;
    }
    // After a gap (an interval over 1.5 times the previous one) the last motion is stale.
    const bool has_two = in.poses >= 2 && in.last_dt_s > 0.0;
    const auto constvel = [&] {
        return has_two ? mapping::PriorConstantVelocity(in.T_world_base_prev2, in.T_world_base_prev,
                                                        in.last_dt_s, in.dt_s, noise)
                       : mapping::PriorFromPreviousPose(in.T_world_base_prev, noise);
    };
    // The trapezoid needs the previous twist at the interval's start, at the usual cadence: after
    // a gap (a dropped scan or more) that twist is stale and the scan's own is held, as the
    // odometry does.
    const auto interval_twist = [&] {
        if (noise.doppler_integration != mapping::TwistIntegration::kTrapezoid || !in.last_twist ||
            !(in.last_dt_s > 0.0 && in.dt_s <= 1.5 * in.last_dt_s))
            return *in.twist;
        return mapping::TrapezoidTwist(*in.last_twist, *in.twist);
    };
    std::optional<mapping::MotionPrior> built;
    PriorSubstitution why_not = PriorSubstitution::kNone;
    switch (in.kind) {
        case PriorKind::kNone:
            built = mapping::PriorFromPreviousPose(in.T_world_base_prev, noise);
            break;
        case PriorKind::kConstVel:
            built = constvel();
            break;
        case PriorKind::kImu: {
            std::optional<Eigen::Vector3d> v_world;  // unknown from one pose
            if (has_two)
                v_world =
                    (in.T_world_base_prev.translation() - in.T_world_base_prev2.translation()) /
                    in.last_dt_s;
            built = mapping::PriorFromImu(in.T_world_base_prev, v_world, in.imu_samples,
                                          in.last_stamp_ns, in.stamp_ns, in.T_base_imu, noise);
            if (!built) why_not = PriorSubstitution::kNoImuSamples;
            break;
        }
        case PriorKind::kDoppler:
        case PriorKind::kImuDoppler:
            if (!in.twist) {
                why_not = in.refused;
            } else if (in.kind == PriorKind::kDoppler) {
                built = mapping::PriorFromDoppler(in.T_world_base_prev, interval_twist(), in.dt_s,
                                                  noise);
            } else {
                built = mapping::PriorFromImuAndDoppler(in.T_world_base_prev, interval_twist(),
                                                        in.imu_samples, in.last_stamp_ns + 1,
                                                        in.stamp_ns, in.T_base_imu, in.dt_s, noise);
                if (!built) why_not = PriorSubstitution::kNoImuSamples;
            }
            if (built && noise.doppler_with_constvel && has_two && in.dt_s <= 1.5 * in.last_dt_s &&
                in.constvel_fusion_allowed)
                built = mapping::FusePriors(*built, constvel());
            break;
    }
    if (!built) {
        out.used = PriorKind::kConstVel;
        out.substitution = why_not;
        if (why_not == PriorSubstitution::kInvalidDopplerVelocity)
            out.substitution_detail = in.refused_detail;
        built = constvel();
    }
    out.prior = *built;
    return out;
}

}  // namespace dorado::frontend
