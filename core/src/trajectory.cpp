#include "dorado/core/trajectory.hpp"

#include <algorithm>
#include <stdexcept>

#include "dorado/core/lie.hpp"

namespace dorado {

Trajectory::Trajectory(std::vector<StampedPose> poses) : poses_(std::move(poses)) {
    std::stable_sort(poses_.begin(), poses_.end(),
                     [](const auto &a, const auto &b) { return a.stamp_ns < b.stamp_ns; });
    for (std::size_t i = 1; i < poses_.size(); ++i) {
        if (poses_[i].stamp_ns == poses_[i - 1].stamp_ns) {
            throw std::invalid_argument("trajectory has two poses at stamp " +
                                        std::to_string(poses_[i].stamp_ns) + " ns");
        }
    }
}

void Trajectory::Append(int64_t stamp_ns, const Eigen::Isometry3d &T_world_body) {
    if (!poses_.empty() && stamp_ns <= poses_.back().stamp_ns) {
        throw std::invalid_argument("trajectory stamps must increase: " + std::to_string(stamp_ns) +
                                    " ns after " + std::to_string(poses_.back().stamp_ns) + " ns");
    }
    poses_.push_back({stamp_ns, T_world_body});
}

std::optional<Eigen::Isometry3d> Trajectory::Interpolate(int64_t stamp_ns,
                                                         int64_t max_gap_ns) const {
    if (poses_.empty() || stamp_ns < poses_.front().stamp_ns || stamp_ns > poses_.back().stamp_ns) {
        return std::nullopt;
    }
    const auto after =
        std::lower_bound(poses_.begin(), poses_.end(), stamp_ns,
                         [](const StampedPose &p, int64_t t) { return p.stamp_ns < t; });
    if (after->stamp_ns == stamp_ns) return after->T_world_body;
    const auto before = std::prev(after);
    const int64_t gap = after->stamp_ns - before->stamp_ns;
    if (gap > max_gap_ns) return std::nullopt;
    const double alpha =
        static_cast<double>(stamp_ns - before->stamp_ns) / static_cast<double>(gap);
    return InterpolatePose(before->T_world_body, after->T_world_body, alpha);
}

double Trajectory::PathLength() const {
    double length = 0.0;
    for (std::size_t i = 1; i < poses_.size(); ++i) {
        length += (poses_[i].T_world_body.translation() - poses_[i - 1].T_world_body.translation())
                      .norm();
    }
    return length;
}

}  // namespace dorado
