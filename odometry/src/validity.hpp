#pragma once
// Internal to dorado_odometry: the validity checks of one ego-velocity estimate, shared by the
// 3-D (ego_velocity.cpp) and the planar (planar_ego_velocity.cpp) estimators.
#include <string>

#include "dorado/odometry/ego_velocity.hpp"

namespace dorado::odometry::internal {

/// A cause with the numbers behind it (EgoVelocityResult::failure and failure_detail).
struct Invalidity {
    EgoVelocityFailure failure = EgoVelocityFailure::kNone;
    std::string detail;
};

/// Why an estimate from `inliers` static points of `points` is not valid (config's validity
/// fields, in this order: inliers, conditioning, finiteness, speed); kNone when it is.
[[nodiscard]] Invalidity CheckValidity(const EgoVelocityConfig &config, int inliers, long points,
                                       double condition_number, bool finite, double speed_mps);

}  // namespace dorado::odometry::internal
