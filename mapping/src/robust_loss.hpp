#pragma once
// Internal: the Ceres loss of a RobustKernel, for the refinement, the pose information and the
// window smoother.

#include <memory>

#include "dorado/mapping/measurements.hpp"

namespace ceres {
class LossFunction;
}

namespace dorado::mapping {

/// The kernel at scale (whitened units); nullptr for kNone.
[[nodiscard]] std::unique_ptr<ceres::LossFunction> MakeLoss(RobustKernel kernel, double scale);

}  // namespace dorado::mapping
