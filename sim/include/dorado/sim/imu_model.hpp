#pragma once
/// @file imu_model.hpp
/// A MEMS IMU (Xsens MTi-30 class) on its own mount: gyro and accelerometer with white noise and
/// a bias that random-walks, sampled at its own rate.

#include <Eigen/Geometry>
#include <cstdint>
#include <random>

#include "dorado/core/imu.hpp"
#include "dorado/sim/sequence_config.hpp"
#include "dorado/sim/vehicle.hpp"

namespace dorado::sim {

class ImuModel {
  public:
    ImuModel(const ImuConfig &config, uint64_t seed);

    /// The measurement at t [s since start], stamped stamp_ns. Call with increasing t: the biases
    /// walk between calls.
    [[nodiscard]] ImuSample Measure(double t, int64_t stamp_ns, const VehicleTrajectory &vehicle);

    [[nodiscard]] const Eigen::Isometry3d &T_base_imu() const { return T_base_imu_; }
    [[nodiscard]] const Eigen::Vector3d &gyro_bias() const { return gyro_bias_; }

  private:
    ImuConfig config_;
    Eigen::Isometry3d T_base_imu_;
    std::mt19937_64 rng_;
    Eigen::Vector3d gyro_bias_;
    Eigen::Vector3d accel_bias_;
    double last_t_ = 0.0;
};

}  // namespace dorado::sim
