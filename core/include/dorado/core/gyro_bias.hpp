#pragma once
/// @file gyro_bias.hpp
/// The gyro bias from the intervals in which the vehicle stands still: a gyro at rest measures
/// its bias (plus the Earth's rotation, 7.3e-5 rad/s, far below a MEMS bias) and noise.

#include <Eigen/Core>
#include <vector>

#include "dorado/core/imu.hpp"

namespace dorado {

/// Mean gyro rate (IMU frame) of the samples taken at rest. An interval counts when the scans at
/// both of its ends are stationary (a scan that stops is not at rest over its whole interval).
/// The mean forgets slowly (an exponential window of `window_samples`) so that a drifting bias is
/// followed at each later stop.
class GyroBiasEstimator {
  public:
    /// `min_samples`: samples at rest before the bias is used (until then it is zero).
    explicit GyroBiasEstimator(int min_samples = 50, int window_samples = 4000);

    /// One scan interval's IMU samples; `stationary`: the scan closing it is at rest.
    void AddInterval(bool stationary, const std::vector<ImuSample> &samples);

    /// True once min_samples samples at rest were seen.
    [[nodiscard]] bool has_bias() const { return count_ >= min_samples_; }
    /// The bias to subtract from the gyro [rad/s, IMU frame]; zero until has_bias().
    [[nodiscard]] Eigen::Vector3d bias_imu_radps() const;
    /// Samples at rest used so far.
    [[nodiscard]] long count() const { return count_; }
    /// The samples with the bias subtracted from their gyro rates.
    [[nodiscard]] std::vector<ImuSample> Corrected(const std::vector<ImuSample> &samples) const;

  private:
    int min_samples_, window_samples_;
    long count_ = 0;
    bool previous_stationary_ = false;
    Eigen::Vector3d mean_ = Eigen::Vector3d::Zero();
};

}  // namespace dorado
