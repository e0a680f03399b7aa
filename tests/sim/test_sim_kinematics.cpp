// The simulated vehicle obeys the kinematics it is built on: checked against closed-form answers.
#include <gtest/gtest.h>

#include <cmath>

#include "dorado/core/lie.hpp"
#include "dorado/sim/terrain.hpp"
#include "dorado/sim/vehicle.hpp"

namespace dorado::sim {
namespace {

SequenceConfig FlatConfig() {
    SequenceConfig config;
    config.duration_s = 20.0;
    config.seed = 3;
    config.terrain.hill_height_m = 0.0;
    config.terrain.roughness_m = 0.0;
    config.terrain.side_slope_height_m = 0.0;
    return config;
}

// On flat ground a point of the Z-ICR axis (x = icr_offset) has no sideways velocity, nothing
// moves vertically, and there is no roll or pitch rate: v_y = -omega_z * icr_offset.
TEST(VehicleTrajectory, FlatGroundFollowsTheIcrConstraint) {
    SequenceConfig config = FlatConfig();
    config.vehicle.icr_offset_m = 0.12;
    const Terrain terrain(config.terrain, config.seed);
    const VehicleTrajectory vehicle(config, terrain);
    double max_speed = 0.0, max_yaw_rate = 0.0;
    for (double t = 0.05; t < config.duration_s - 0.05; t += 0.137) {
        const Twist twist = vehicle.Twist(t);
        EXPECT_NEAR(twist.v_base_mps.y(), -twist.omega_base_radps.z() * 0.12, 1e-5) << "t = " << t;
        EXPECT_NEAR(twist.v_base_mps.z(), 0.0, 1e-6);
        EXPECT_NEAR(twist.omega_base_radps.x(), 0.0, 1e-6);
        EXPECT_NEAR(twist.omega_base_radps.y(), 0.0, 1e-6);
        max_speed = std::max(max_speed, std::abs(twist.v_base_mps.x()));
        max_yaw_rate = std::max(max_yaw_rate, std::abs(twist.omega_base_radps.z()));
    }
    // The check above must not pass vacuously on a vehicle that stands still.
    EXPECT_GT(max_speed, 0.5);
    EXPECT_GT(max_yaw_rate, 0.1);
}

// The twist integrates back to the poses: exp of the body twist over a short step maps
// Pose(t) onto Pose(t + dt) (to second order in dt).
TEST(VehicleTrajectory, TwistIntegratesToPoseOnHills) {
    SequenceConfig config = FlatConfig();
    config.terrain.hill_height_m = 1.0;
    config.terrain.hill_wavelength_m = 30.0;
    config.terrain.side_slope_height_m = 0.1;
    const Terrain terrain(config.terrain, config.seed);
    const VehicleTrajectory vehicle(config, terrain);
    constexpr double dt = 1e-3;
    double max_pitch_rate = 0.0;
    for (double t = 2.0; t < 19.0; t += 0.5) {
        const Twist twist = vehicle.Twist(t + 0.5 * dt);
        Vector6d xi;
        xi << twist.v_base_mps * dt, twist.omega_base_radps * dt;
        const Eigen::Isometry3d predicted = vehicle.Pose(t) * ExpSE3(xi);
        const Eigen::Isometry3d actual = vehicle.Pose(t + dt);
        EXPECT_LT((predicted.translation() - actual.translation()).norm(), 1e-6);
        EXPECT_LT(RotationAngle(predicted.linear().transpose() * actual.linear()), 1e-7);
        max_pitch_rate = std::max(max_pitch_rate, std::abs(twist.omega_base_radps.y()));
    }
    EXPECT_GT(max_pitch_rate, 0.01);  // the hills do pitch the vehicle
}

// The base sits wheel_radius above the ground under the rear axle.
TEST(VehicleTrajectory, RestsOnTheTerrain) {
    SequenceConfig config = FlatConfig();
    config.terrain.hill_height_m = 1.5;
    const Terrain terrain(config.terrain, config.seed);
    const VehicleTrajectory vehicle(config, terrain);
    for (double t = 0.0; t < 20.0; t += 1.0) {
        const Eigen::Isometry3d T = vehicle.Pose(t);
        const Eigen::Vector3d axle_ground =
            T * Eigen::Vector3d(0, 0, -config.vehicle.wheel_radius_m);
        EXPECT_NEAR(axle_ground.z(), terrain.Height(axle_ground.x(), axle_ground.y()), 0.02);
    }
}

}  // namespace
}  // namespace dorado::sim
