#pragma once
/// @file absolute_trajectory_error.hpp
/// Absolute trajectory error (ATE): position error after aligning the estimate onto the reference
/// with Umeyama's closed form (SE(3), or Sim(3) for scale-free methods), as evo_ape -a [-s].

#include <Eigen/Geometry>
#include <vector>

#include "dorado/eval/association.hpp"

namespace dorado::eval {

struct AteOptions {
    bool with_scale = false;  ///< Sim(3) instead of SE(3)
};

struct AteResult {
    /// x_ref ~= scale * R * x_est + t: rotation and translation in T_ref_est, scale separately.
    Eigen::Isometry3d T_ref_est = Eigen::Isometry3d::Identity();
    double scale = 1.0;
    std::vector<double> translation_m;  ///< |p_ref - (scale R p_est + t)| per associated pose
};

/// Throws std::invalid_argument with fewer than 3 associated poses (the alignment is undetermined).
[[nodiscard]] AteResult ComputeAte(const AssociatedPoses &poses, const AteOptions &options = {});

}  // namespace dorado::eval
