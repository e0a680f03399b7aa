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

}  // namespace dorado
