#include "dorado/eval/end_point_error.hpp"

#include <limits>
#include <stdexcept>

namespace dorado::eval {

EndPointError ComputeEndPointError(const AssociatedPoses &poses) {
    const std::size_t n = poses.size();
    if (n < 2) throw std::invalid_argument("end-point error: needs at least 2 associated poses");
    EndPointError result;
    for (std::size_t k = 1; k < n; ++k)
        result.path_length_m +=
            (poses.T_world_ref[k].translation() - poses.T_world_ref[k - 1].translation()).norm();
    // The estimate's frame put on the reference's at the first pose: world_ref <- world_est.
    const Eigen::Isometry3d T_ref_est =
        poses.T_world_ref.front() * poses.T_world_est.front().inverse();
    const Eigen::Vector3d end_est = (T_ref_est * poses.T_world_est.back()).translation();
    result.error_m = (end_est - poses.T_world_ref.back().translation()).norm();
    result.percent = result.path_length_m > 0.0 ? 100.0 * result.error_m / result.path_length_m
                                                : std::numeric_limits<double>::quiet_NaN();
    return result;
}

}  // namespace dorado::eval
