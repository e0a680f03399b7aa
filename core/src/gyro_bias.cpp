#include "dorado/core/gyro_bias.hpp"

#include <algorithm>
#include <stdexcept>

namespace dorado {

GyroBiasEstimator::GyroBiasEstimator(int min_samples, int window_samples)
    : min_samples_(min_samples), window_samples_(window_samples) {
    if (min_samples < 1 || window_samples < min_samples)
        throw std::invalid_argument("GyroBiasEstimator: need 1 <= min_samples <= window_samples");
}

void GyroBiasEstimator::AddInterval(bool stationary, const std::vector<ImuSample> &samples) {
    const bool at_rest = stationary && previous_stationary_;
    previous_stationary_ = stationary;
    if (!at_rest) return;
    for (const ImuSample &sample : samples) {
        if (!sample.omega_imu_radps.allFinite()) continue;
        ++count_;
        // Running mean, then an exponential window once window_samples are in.
        const double gain = 1.0 / static_cast<double>(std::min<long>(count_, window_samples_));
        mean_ += gain * (sample.omega_imu_radps - mean_);
    }
}

Eigen::Vector3d GyroBiasEstimator::bias_imu_radps() const {
    return has_bias() ? mean_ : Eigen::Vector3d::Zero();
}

std::vector<ImuSample> GyroBiasEstimator::Corrected(const std::vector<ImuSample> &samples) const {
    std::vector<ImuSample> corrected = samples;
    const Eigen::Vector3d bias = bias_imu_radps();
    for (ImuSample &sample : corrected) sample.omega_imu_radps -= bias;
    return corrected;
}

}  // namespace dorado
