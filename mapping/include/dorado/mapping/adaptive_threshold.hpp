#pragma once
/// @file adaptive_threshold.hpp
/// The correspondence threshold of kiss-icp (Vizzo et al. 2023, section III-C): three times the
/// standard deviation of how far registration moved the pose away from the motion prediction,
/// measured as the displacement of a point at max_range.

#include <Eigen/Geometry>

namespace dorado::mapping {

class AdaptiveThreshold {
  public:
    /// initial_threshold_m is used until a deviation above min_motion_m has been seen;
    /// min_threshold_m is a floor (radar points are noisy at the decimetre level).
    AdaptiveThreshold(double initial_threshold_m, double min_threshold_m, double min_motion_m,
                      double max_range_m);

    /// Records the correction T_prior^-1 * T_registered of one scan.
    void Update(const Eigen::Isometry3d &model_deviation);

    /// Current threshold [m].
    [[nodiscard]] double Threshold() const;

  private:
    double initial_threshold_m_;
    double min_threshold_m_;
    double min_motion_m_;
    double max_range_m_;
    double sum_squared_error_ = 0.0;
    int count_ = 0;
};

}  // namespace dorado::mapping
