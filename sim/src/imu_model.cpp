#include "dorado/sim/imu_model.hpp"

#include <cmath>

namespace dorado::sim {

namespace {

Eigen::Vector3d Gaussian3(std::mt19937_64 &rng) {
    std::normal_distribution<double> n(0.0, 1.0);
    return {n(rng), n(rng), n(rng)};
}

}  // namespace

ImuModel::ImuModel(const ImuConfig &config, uint64_t seed)
    : config_(config), T_base_imu_(config.mount.Transform()), rng_(seed ^ 0x1a0b5e7ull) {
    gyro_bias_ = config.gyro_bias_sigma_radps * Gaussian3(rng_);
    accel_bias_ = config.accel_bias_sigma_mps2 * Gaussian3(rng_);
}

ImuSample ImuModel::Measure(double t, int64_t stamp_ns, const VehicleTrajectory &vehicle) {
    const double dt = std::max(0.0, t - last_t_);
    last_t_ = t;
    gyro_bias_ += config_.gyro_bias_walk * std::sqrt(dt) * Gaussian3(rng_);
    accel_bias_ += config_.accel_bias_walk * std::sqrt(dt) * Gaussian3(rng_);
    // Discrete white noise: density * sqrt(sample rate).
    const double root_rate = std::sqrt(config_.rate_hz);

    const Eigen::Isometry3d T_world_base = vehicle.Pose(t);
    const Twist twist = vehicle.Twist(t);
    const Eigen::Matrix3d R_imu_base = T_base_imu_.linear().transpose();
    const Eigen::Matrix3d R_imu_world = R_imu_base * T_world_base.linear().transpose();
    // Specific force: acceleration of the IMU's point minus gravity (0, 0, -9.81).
    const Eigen::Vector3d a_world = vehicle.PointAccelerationWorld(t, T_base_imu_.translation());
    const Eigen::Vector3d specific_force_world = a_world + Eigen::Vector3d(0.0, 0.0, 9.81);

    ImuSample sample;
    sample.stamp_ns = stamp_ns;
    sample.omega_imu_radps = R_imu_base * twist.omega_base_radps + gyro_bias_ +
                             config_.gyro_noise_density * root_rate * Gaussian3(rng_);
    sample.accel_imu_mps2 = R_imu_world * specific_force_world + accel_bias_ +
                            config_.accel_noise_density * root_rate * Gaussian3(rng_);
    return sample;
}

}  // namespace dorado::sim
