#include "dorado/eval/kitti_drift.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "dorado/core/angles.hpp"

namespace dorado::eval {

DriftResult ComputeKittiDrift(const AssociatedPoses &poses, const DriftConfig &config) {
    if (config.lengths_m.empty()) throw std::invalid_argument("kitti drift: no segment length");
    for (double length : config.lengths_m)
        if (!(length > 0.0)) throw std::invalid_argument("kitti drift: lengths must be > 0");
    if (config.step_frames < 1) throw std::invalid_argument("kitti drift: step_frames >= 1");
    const std::size_t n = poses.size();
    // Path length of the reference up to each pose (the devkit's trajectoryDistances).
    std::vector<double> distance(n, 0.0);
    for (std::size_t k = 1; k < n; ++k)
        distance[k] =
            distance[k - 1] +
            (poses.T_world_ref[k].translation() - poses.T_world_ref[k - 1].translation()).norm();
    DriftResult result;
    double sum_t = 0.0, sum_r = 0.0;
    for (std::size_t first = 0; first < n; first += config.step_frames) {
        for (double length : config.lengths_m) {
            // The first pose at least `length` further along the reference (the devkit's
            // lastFrameFromSegmentLength: distance > start + length).
            std::size_t last = first;
            while (last < n && !(distance[last] > distance[first] + length)) ++last;
            if (last >= n) continue;
            const Eigen::Isometry3d delta_ref =
                poses.T_world_ref[first].inverse() * poses.T_world_ref[last];
            const Eigen::Isometry3d delta_est =
                poses.T_world_est[first].inverse() * poses.T_world_est[last];
            const Eigen::Isometry3d error = delta_est.inverse() * delta_ref;
            sum_t += error.translation().norm() / length;
            sum_r += Eigen::AngleAxisd(error.linear()).angle() / length;
            ++result.segments;
        }
    }
    if (result.segments > 0) {
        result.translation_percent = 100.0 * sum_t / result.segments;
        result.rotation_deg_per_100m = 100.0 * RadToDeg(sum_r) / result.segments;
    }
    return result;
}

}  // namespace dorado::eval
