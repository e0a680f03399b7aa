#pragma once
/// @file imu.hpp
/// Inertial measurements, in the IMU's own frame ("imu").

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace dorado {

struct ImuSample {
    int64_t stamp_ns = 0;
    Eigen::Vector3d omega_imu_radps = Eigen::Vector3d::Zero();  ///< gyro [rad/s]
    Eigen::Vector3d accel_imu_mps2 = Eigen::Vector3d::Zero();   ///< specific force [m/s^2]
};

/// Mean gyro rate over the samples with stamps in [t0_ns, t1_ns]; empty samples give NaN.
[[nodiscard]] Eigen::Vector3d MeanAngularVelocity(const std::vector<ImuSample> &samples,
                                                  int64_t t0_ns, int64_t t1_ns);

/// The IMU samples between two scans: samples arrive one by one, each scan interval
/// (t_prev, t_scan] takes the ones inside it. The one gyro window of the odometry, the mapper's
/// priors and the calibration.
class ImuWindow {
  public:
    /// Buffers a sample; samples with a NaN/Inf gyro or accelerometer value are ignored.
    void Add(const ImuSample &sample);
    /// The samples with stamps in (t0_ns, t1_ns], in arrival order.
    [[nodiscard]] std::vector<ImuSample> Between(int64_t t0_ns, int64_t t1_ns) const;
    /// Mean gyro rate over (t0_ns, t1_ns] in the IMU frame; NaN when no sample is inside.
    [[nodiscard]] Eigen::Vector3d MeanGyro(int64_t t0_ns, int64_t t1_ns) const;
    /// Drops the samples with stamps <= t_ns (used by a scan at t_ns).
    void DropUpTo(int64_t t_ns);
    /// Every buffered sample, in arrival order.
    [[nodiscard]] const std::vector<ImuSample> &samples() const { return samples_; }
    [[nodiscard]] std::size_t size() const { return samples_.size(); }
    /// Stamp of the newest sample ever added (0 when none).
    [[nodiscard]] int64_t newest_stamp_ns() const { return newest_stamp_ns_; }

  private:
    std::vector<ImuSample> samples_;
    int64_t newest_stamp_ns_ = 0;
};

}  // namespace dorado
