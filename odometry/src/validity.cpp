#include "validity.hpp"

#include <sstream>

namespace dorado::odometry {
namespace {

std::string Format(double value) {
    std::ostringstream s;
    s.precision(4);
    s << value;
    return s.str();
}

}  // namespace

const char *ToString(EgoVelocityFailure failure) {
    switch (failure) {
        case EgoVelocityFailure::kNone:
            return "";
        case EgoVelocityFailure::kNotEstimated:
            return "not estimated";
        case EgoVelocityFailure::kEmptyScan:
            return "empty scan";
        case EgoVelocityFailure::kTooFewPoints:
            return "too few points after the pre-filters";
        case EgoVelocityFailure::kZeroWeight:
            return "every point has zero weight (power at or below decibel_floor_db)";
        case EgoVelocityFailure::kDegenerateGeometry:
            return "degenerate geometry";
        case EgoVelocityFailure::kTooFewInliers:
            return "too few static inliers";
        case EgoVelocityFailure::kNonFinite:
            return "non-finite velocity or covariance";
        case EgoVelocityFailure::kSpeedLimit:
            return "speed above max_speed_mps";
        case EgoVelocityFailure::kNoPlanarModel:
            return "no planar vehicle model";
    }
    return "?";
}

std::string Describe(const EgoVelocityResult &result) {
    std::string text = ToString(result.failure);
    if (!result.valid() && !result.failure_detail.empty()) text += ": " + result.failure_detail;
    return text;
}

namespace internal {

Invalidity CheckValidity(const EgoVelocityConfig &config, int inliers, long points,
                         double condition_number, bool finite, double speed_mps) {
    const double ratio = static_cast<double>(inliers) / static_cast<double>(points);
    if (inliers < config.min_inliers || ratio < config.min_inlier_ratio)
        return {EgoVelocityFailure::kTooFewInliers,
                std::to_string(inliers) + " of " + std::to_string(points) +
                    " points (min_inliers " + std::to_string(config.min_inliers) +
                    ", min_inlier_ratio " + Format(config.min_inlier_ratio) + ")"};
    if (!(condition_number <= config.max_condition_number))
        return {EgoVelocityFailure::kDegenerateGeometry,
                "condition number " + Format(condition_number) + " > max_condition_number " +
                    Format(config.max_condition_number)};
    if (!finite) return {EgoVelocityFailure::kNonFinite, ""};
    if (speed_mps > config.max_speed_mps)
        return {EgoVelocityFailure::kSpeedLimit,
                Format(speed_mps) + " m/s > " + Format(config.max_speed_mps)};
    return {};
}

}  // namespace internal
}  // namespace dorado::odometry
