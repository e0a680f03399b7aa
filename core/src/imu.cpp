#include "dorado/core/imu.hpp"

#include <limits>

namespace dorado {

Eigen::Vector3d MeanAngularVelocity(const std::vector<ImuSample> &samples, int64_t t0_ns,
                                    int64_t t1_ns) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int count = 0;
    for (const auto &s : samples) {
        if (s.stamp_ns < t0_ns || s.stamp_ns > t1_ns) continue;
        sum += s.omega_imu_radps;
        ++count;
    }
    if (count == 0) return Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    return sum / count;
}

}  // namespace dorado
