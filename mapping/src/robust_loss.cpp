#include "robust_loss.hpp"

#include <ceres/loss_function.h>

namespace dorado::mapping {

std::unique_ptr<ceres::LossFunction> MakeLoss(RobustKernel kernel, double scale) {
    switch (kernel) {
        case RobustKernel::kNone:
            return nullptr;
        case RobustKernel::kHuber:
            return std::make_unique<ceres::HuberLoss>(scale);
        case RobustKernel::kCauchy:
            return std::make_unique<ceres::CauchyLoss>(scale);
        case RobustKernel::kTukey:
            return std::make_unique<ceres::TukeyLoss>(scale);
    }
    return nullptr;
}

}  // namespace dorado::mapping
