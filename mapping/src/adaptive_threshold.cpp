#include "dorado/mapping/adaptive_threshold.hpp"

#include <algorithm>
#include <cmath>

#include "dorado/core/lie.hpp"

namespace dorado::mapping {

AdaptiveThreshold::AdaptiveThreshold(double initial_threshold_m, double min_threshold_m,
                                     double min_motion_m, double max_range_m)
    : initial_threshold_m_(initial_threshold_m),
      min_threshold_m_(min_threshold_m),
      min_motion_m_(min_motion_m),
      max_range_m_(max_range_m) {}

void AdaptiveThreshold::Update(const Eigen::Isometry3d &model_deviation) {
    // kiss-icp eq. (6): the deviation's effect on a point at max range, rotation (chord of the arc)
    // plus translation.
    const double theta = RotationAngle(model_deviation.linear());
    const double error =
        2.0 * max_range_m_ * std::sin(theta / 2.0) + model_deviation.translation().norm();
    if (error > min_motion_m_) {
        sum_squared_error_ += error * error;
        ++count_;
    }
}

double AdaptiveThreshold::Threshold() const {
    if (count_ == 0) return initial_threshold_m_;
    // 3 sigma of the deviations seen so far.
    return std::max(min_threshold_m_, 3.0 * std::sqrt(sum_squared_error_ / count_));
}

}  // namespace dorado::mapping
