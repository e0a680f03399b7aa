// CompareWithImu on a simulated rig whose velocity and rotation are known in closed form: the IMU
// samples are the exact specific force and rate, the radar velocities the exact ones. The check
// must find slope 1 and the sign, -1 for negated Doppler, and recover a known extrinsic error.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "dorado/core/lie.hpp"
#include "dorado/odometry/inertial_check.hpp"

namespace dorado::odometry {
namespace {

constexpr double kStart = 1.5;  // at rest before (the rest window is the first second)
const Eigen::Vector3d kOmega(0.3, -0.2, 0.5);  // body rate after the start [rad/s]
const Eigen::Vector3d kGravity(0.0, 0.0, -9.81);

double Ramp(double t) {
    return t < kStart ? 0.0 : t - kStart;
}
// World velocity and acceleration (zero before the start, smooth after).
Eigen::Vector3d VWorld(double t) {
    const double u = Ramp(t);
    return Eigen::Vector3d(std::sin(u) * std::sin(u), 0.5 * (1.0 - std::cos(2.0 * u)) * 0.8,
                           0.2 * std::sin(u) * std::sin(u));
}
Eigen::Vector3d AWorld(double t) {
    const double u = Ramp(t);
    return t < kStart
               ? Eigen::Vector3d::Zero()
               : Eigen::Vector3d(std::sin(2 * u), 0.8 * std::sin(2 * u), 0.2 * std::sin(2 * u));
}
Eigen::Matrix3d RWorldImu(double t) {
    return ExpSO3(kOmega * Ramp(t));
}
Eigen::Vector3d Rate(double t) {
    return t < kStart ? Eigen::Vector3d::Zero() : kOmega;
}

struct Data {
    Extrinsics extrinsics;
    std::vector<ImuSample> imu;
    std::vector<StampedRadarVelocity> velocities;
};

Data Simulate() {
    Data d;  // base = IMU; the radar 10 cm away, turned
    d.extrinsics.T_base_radar.translation() = Eigen::Vector3d(0.1, -0.05, 0.03);
    d.extrinsics.T_base_radar.linear() = ExpSO3(Eigen::Vector3d(2.9, 0.4, -0.2));
    for (int k = 0; k <= 2000; ++k) {  // 200 Hz, 10 s
        const double t = k * 0.005;
        ImuSample s;
        s.stamp_ns = static_cast<int64_t>(k) * 5'000'000;
        s.omega_imu_radps = Rate(t);
        s.accel_imu_mps2 = RWorldImu(t).transpose() * (AWorld(t) - kGravity);
        d.imu.push_back(s);
    }
    const Eigen::Matrix3d R_br = d.extrinsics.T_base_radar.linear();
    const Eigen::Vector3d p_br = d.extrinsics.T_base_radar.translation();
    for (int k = 0; k < 100; ++k) {  // 10 Hz, stamps between IMU samples
        const double t = 0.0523 + k * 0.1;
        const Eigen::Vector3d v_base = RWorldImu(t).transpose() * VWorld(t);
        const Eigen::Vector3d v_radar = R_br.transpose() * (v_base + Rate(t).cross(p_br));
        d.velocities.push_back({static_cast<int64_t>(t * 1e9), v_radar});
    }
    return d;
}

TEST(InertialCheck, ExactDataGiveSlopeOneAndTheSign) {
    const Data d = Simulate();
    const InertialCheck c = CompareWithImu(d.velocities, d.imu, d.extrinsics);
    ASSERT_GE(c.as_given.windows, 70);
    EXPECT_EQ(c.doppler_sign, 1);
    EXPECT_NEAR(c.as_given.slope, 1.0, 0.01);
    EXPECT_LT(c.as_given.rms_residual_mps, 0.02 * c.as_given.rms_delta_v_mps);
    EXPECT_NEAR(c.flipped.slope, -1.0, 0.1);
    EXPECT_LT(c.rotation_correction_base_rad.norm(), 0.002);
    EXPECT_LT(c.gyro_bias_imu_radps.norm(), 1e-12);

    std::vector<StampedRadarVelocity> negated = d.velocities;
    for (auto &v : negated) v.v_radar_mps = -v.v_radar_mps;
    EXPECT_EQ(CompareWithImu(negated, d.imu, d.extrinsics).doppler_sign, -1);
}

TEST(InertialCheck, RecoversAnExtrinsicRotationError) {
    const Data d = Simulate();
    Extrinsics wrong = d.extrinsics;
    const Eigen::Vector3d error(0.03, -0.05, 0.02);  // [rad], ~3.4 deg
    wrong.T_base_radar.linear() = ExpSO3(error) * d.extrinsics.T_base_radar.linear();
    const InertialCheck c = CompareWithImu(d.velocities, d.imu, wrong);
    // The correction undoes the error (linearised, so to second order).
    EXPECT_LT((c.rotation_correction_base_rad + error).norm(), 0.005);
    EXPECT_LT(c.rms_residual_corrected_mps, 0.3 * c.as_given.rms_residual_mps);
}

TEST(InertialCheck, FindsAKnownTimeOffset) {
    Data d = Simulate();
    for (auto &v : d.velocities) v.stamp_ns += 40'000'000;  // stamped 40 ms late
    InertialCheckConfig config;
    config.max_time_offset_s = 0.1;
    const InertialCheck c = CompareWithImu(d.velocities, d.imu, d.extrinsics, config);
    EXPECT_NEAR(c.best_time_offset_s, -0.04, 0.0051);
}

}  // namespace
}  // namespace dorado::odometry
