#include "dorado/eval/absolute_trajectory_error.hpp"

#include <Eigen/Geometry>
#include <stdexcept>
#include <string>

namespace dorado::eval {

AteResult ComputeAte(const AssociatedPoses &poses, const AteOptions &options) {
    const auto n = static_cast<Eigen::Index>(poses.size());
    if (n < 3) {
        throw std::invalid_argument("ATE needs at least 3 associated poses, got " +
                                    std::to_string(n));
    }
    Eigen::Matrix3Xd p_est(3, n);
    Eigen::Matrix3Xd p_ref(3, n);
    for (Eigen::Index k = 0; k < n; ++k) {
        p_est.col(k) = poses.T_world_est[static_cast<std::size_t>(k)].translation();
        p_ref.col(k) = poses.T_world_ref[static_cast<std::size_t>(k)].translation();
    }
    // Umeyama (1991) least-squares similarity taking the estimate onto the reference.
    const Eigen::Matrix4d sim = Eigen::umeyama(p_est, p_ref, options.with_scale);
    AteResult out;
    out.scale = options.with_scale ? std::cbrt(sim.topLeftCorner<3, 3>().determinant()) : 1.0;
    out.T_ref_est.linear() = sim.topLeftCorner<3, 3>() / out.scale;
    out.T_ref_est.translation() = sim.topRightCorner<3, 1>();
    const Eigen::Matrix3Xd p_aligned =
        (out.scale * out.T_ref_est.linear() * p_est).colwise() + out.T_ref_est.translation();
    out.translation_m.resize(static_cast<std::size_t>(n));
    for (Eigen::Index k = 0; k < n; ++k) {
        out.translation_m[static_cast<std::size_t>(k)] = (p_ref.col(k) - p_aligned.col(k)).norm();
    }
    return out;
}

}  // namespace dorado::eval
