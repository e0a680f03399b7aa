// The simulated IMU measures the true motion: its mean gyro equals the true angular velocity and,
// standing still, its accelerometer reads gravity.
#include <gtest/gtest.h>

#include <cmath>

#include "dorado/core/time.hpp"
#include "dorado/sim/imu_model.hpp"
#include "dorado/sim/terrain.hpp"
#include "dorado/sim/vehicle.hpp"

namespace dorado::sim {
namespace {

SequenceConfig HillyConfig() {
    SequenceConfig config;
    config.duration_s = 30.0;
    config.seed = 4;
    config.terrain.hill_height_m = 1.0;
    config.terrain.roughness_m = 0.01;
    config.imu.mount.translation_m = {0.3, -0.05, 0.25};
    config.imu.mount.rotation_rpy_deg = {10.0, -5.0, 90.0};
    config.imu.gyro_bias_sigma_radps = 0.0;  // white noise only: the mean must converge
    config.imu.gyro_bias_walk = 0.0;
    return config;
}

TEST(ImuModel, MeanGyroMatchesTrueAngularVelocity) {
    const SequenceConfig config = HillyConfig();
    const Terrain terrain(config.terrain, config.seed);
    const VehicleTrajectory vehicle(config, terrain);
    ImuModel imu(config.imu, config.seed);
    const Eigen::Matrix3d R_base_imu = config.imu.mount.Transform().linear();
    const double sigma = config.imu.gyro_noise_density * std::sqrt(config.imu.rate_hz);
    // Windows of 2 s (400 samples): the mean error must be within 4 sigma / sqrt(n).
    for (double t0 = 2.0; t0 < 28.0; t0 += 2.0) {
        Eigen::Vector3d measured = Eigen::Vector3d::Zero(), truth = Eigen::Vector3d::Zero();
        int n = 0;
        for (double t = t0; t < t0 + 2.0; t += 1.0 / config.imu.rate_hz, ++n) {
            const ImuSample s = imu.Measure(t, SecondsToNanos(t), vehicle);
            measured += R_base_imu * s.omega_imu_radps;
            truth += vehicle.Twist(t).omega_base_radps;
        }
        measured /= n;
        truth /= n;
        EXPECT_LT((measured - truth).cwiseAbs().maxCoeff(), 4.0 * sigma / std::sqrt(n))
            << "t0 = " << t0;
    }
}

TEST(ImuModel, BiasShiftsTheMeanByTheBias) {
    SequenceConfig config = HillyConfig();
    config.imu.gyro_bias_sigma_radps = 0.01;
    const Terrain terrain(config.terrain, config.seed);
    const VehicleTrajectory vehicle(config, terrain);
    ImuModel imu(config.imu, config.seed);
    const Eigen::Matrix3d R_imu_base = config.imu.mount.Transform().linear().transpose();
    Eigen::Vector3d error = Eigen::Vector3d::Zero();
    int n = 0;
    for (double t = 5.0; t < 15.0; t += 0.005, ++n) {
        error += imu.Measure(t, SecondsToNanos(t), vehicle).omega_imu_radps -
                 R_imu_base * vehicle.Twist(t).omega_base_radps;
    }
    error /= n;
    EXPECT_GT(imu.gyro_bias().norm(), 1e-3);
    EXPECT_LT((error - imu.gyro_bias()).norm(), 5e-4);
}

TEST(ImuModel, AccelerometerReadsGravityStandingStill) {
    SequenceConfig config = HillyConfig();
    config.imu.accel_bias_sigma_mps2 = 0.0;
    config.imu.accel_bias_walk = 0.0;
    const Terrain terrain(config.terrain, config.seed);
    const VehicleTrajectory vehicle(config, terrain);  // the first second is standing still
    ImuModel imu(config.imu, config.seed);
    const Eigen::Isometry3d T_world_imu = vehicle.Pose(0.5) * config.imu.mount.Transform();
    const Eigen::Vector3d expected = T_world_imu.linear().transpose() * Eigen::Vector3d(0, 0, 9.81);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    int n = 0;
    for (double t = 0.1; t < 0.9; t += 0.005, ++n)
        mean += imu.Measure(t, SecondsToNanos(t), vehicle).accel_imu_mps2;
    mean /= n;
    EXPECT_LT((mean - expected).norm(), 5e-3);
    EXPECT_GT(std::abs(expected.x()) + std::abs(expected.y()), 0.5);  // the mount is tilted
}

}  // namespace
}  // namespace dorado::sim
