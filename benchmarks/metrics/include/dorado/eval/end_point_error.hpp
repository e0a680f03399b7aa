#pragma once
/// @file end_point_error.hpp
/// The end-point error of an estimated trajectory: the estimate's start put on the reference's
/// start (position and orientation: T_align = T_world_ref[0] T_world_est[0]^-1), the distance
/// between where the estimate then ends and where the reference ends, in metres and in percent of
/// the reference's path length over the same poses. No other alignment: the error dead reckoning
/// accumulates, as a driven loop's closure gap or a drive's final offset is quoted.

#include "dorado/eval/association.hpp"

namespace dorado::eval {

struct EndPointError {
    double error_m = 0.0;        ///< |t(T_align T_world_est[last]) - t(T_world_ref[last])|
    double path_length_m = 0.0;  ///< the reference's path, summed pose to pose
    double percent = 0.0;        ///< 100 error_m / path_length_m (NaN for a path of 0 m)
};

/// Throws std::invalid_argument for fewer than 2 associated poses.
[[nodiscard]] EndPointError ComputeEndPointError(const AssociatedPoses &poses);

}  // namespace dorado::eval
