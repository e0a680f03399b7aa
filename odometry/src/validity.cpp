#include "validity.hpp"

#include <sstream>

namespace dorado::odometry::internal {
namespace {

std::string Format(double value) {
    std::ostringstream s;
    s.precision(4);
    s << value;
    return s.str();
}

}  // namespace

std::string InvalidityReason(const EgoVelocityConfig &config, int inliers, long points,
                             double condition_number, bool finite, double speed_mps) {
    const double ratio = static_cast<double>(inliers) / static_cast<double>(points);
    if (inliers < config.min_inliers || ratio < config.min_inlier_ratio)
        return "too few static inliers: " + std::to_string(inliers) + " of " +
               std::to_string(points) + " points (min_inliers " +
               std::to_string(config.min_inliers) + ", min_inlier_ratio " +
               Format(config.min_inlier_ratio) + ")";
    if (!(condition_number <= config.max_condition_number))
        return "degenerate geometry: condition number " + Format(condition_number) +
               " > max_condition_number " + Format(config.max_condition_number);
    if (!finite) return "non-finite velocity or covariance";
    if (speed_mps > config.max_speed_mps)
        return "speed " + Format(speed_mps) + " m/s above max_speed_mps " +
               Format(config.max_speed_mps);
    return "";
}

}  // namespace dorado::odometry::internal
