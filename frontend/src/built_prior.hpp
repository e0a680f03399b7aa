#pragma once
// Internal: the motion prior of one scan, as both front ends build it (motion_prior_step.cpp for
// one radar, multi_radar_front_end.cpp for a sweep of several): they differ only in where the
// Doppler twist and the IMU samples come from, which the caller puts in PriorInputs.

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "dorado/core/imu.hpp"
#include "dorado/frontend/radar_front_end.hpp"

namespace dorado::frontend {

/// The motion prior of one scan, and how it was chosen.
struct BuiltPrior {
    mapping::MotionPrior prior;
    mapping::PriorKind requested = mapping::PriorKind::kDoppler;
    mapping::PriorKind used = mapping::PriorKind::kDoppler;
    bool first_scan = false;  ///< the first scan after a reset: the world's origin
    PriorSubstitution substitution = PriorSubstitution::kNone;
    std::string substitution_detail;
};

/// What one scan's prior is built from.
struct PriorInputs {
    mapping::PriorKind kind = mapping::PriorKind::kDoppler;
    /// Poses since the last reset (0: this scan is the first and defines the world).
    int poses = 0;
    Eigen::Isometry3d T_world_base_first = Eigen::Isometry3d::Identity();  ///< poses == 0
    Eigen::Isometry3d T_world_base_prev = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_world_base_prev2 = Eigen::Isometry3d::Identity();
    int64_t last_stamp_ns = 0;  ///< the previous pose's
    int64_t stamp_ns = 0;
    double last_dt_s = 0.0;  ///< between the two previous poses (0: unknown)
    double dt_s = 0.0;       ///< since the previous pose
    /// This scan's base twist; nullopt when the Doppler twist is refused, for `refused`'s reason.
    std::optional<Twist> twist;
    /// The previous pose's twist (nullopt: none), the interval's start for the trapezoid.
    std::optional<Twist> last_twist;
    PriorSubstitution refused = PriorSubstitution::kNone;
    std::string refused_detail;
    /// The IMU samples since the previous pose (bias-corrected where the caller corrects it).
    std::vector<ImuSample> imu_samples;
    Eigen::Isometry3d T_base_imu = Eigen::Isometry3d::Identity();
    /// The Doppler prior may be fused with constvel (doppler_with_constvel) on this scan: false on
    /// a stationary scan, whose zero twist is exact.
    bool constvel_fusion_allowed = true;
};

/// The prior of `in.kind`, or `constvel` in its place (with the cause) when it cannot be built.
[[nodiscard]] BuiltPrior BuildMotionPrior(const PriorInputs &in,
                                          const mapping::PriorNoiseConfig &noise);

}  // namespace dorado::frontend
