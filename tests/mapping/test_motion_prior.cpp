// Motion priors against closed-form motions.
#include <gtest/gtest.h>

#include "dorado/core/lie.hpp"
#include "dorado/core/time.hpp"
#include "dorado/mapping/motion_prior.hpp"

namespace dorado::mapping {
namespace {

Vector6d Xi(double a, double b, double c, double d, double e, double f) {
    Vector6d xi;
    xi << a, b, c, d, e, f;
    return xi;
}

double PoseError(const Eigen::Isometry3d &A, const Eigen::Isometry3d &B) {
    return LogSE3(A.inverse() * B).norm();
}

TEST(MotionPrior, ConstantVelocityReplaysTheLastMotionScaledByTime) {
    const Eigen::Isometry3d T0 = ExpSE3(Xi(1, 2, 0, 0, 0, 0.3));
    const Vector6d twist = Xi(8.0, 0.1, 0.0, 0.0, 0.01, 0.2);  // per second
    const Eigen::Isometry3d T1 = T0 * ExpSE3(twist * 0.1);
    const MotionPrior prior = PriorConstantVelocity(T0, T1, 0.1, 0.05, PriorNoiseConfig{});
    EXPECT_LT(PoseError(prior.T_world_base, T1 * ExpSE3(twist * 0.05)), 1e-12);
    EXPECT_EQ(prior.kind, PriorKind::kConstVel);
    EXPECT_THROW((void)PriorConstantVelocity(T0, T1, 0.0, 0.1, PriorNoiseConfig{}),
                 std::invalid_argument);
}

TEST(MotionPrior, DopplerIsAConstantTwistWithCovarianceScaledByDtSquaredAndRollFloor) {
    const Eigen::Isometry3d T0 = ExpSE3(Xi(5, -1, 0.2, 0.01, 0.02, -0.4));
    Twist twist;
    twist.v_base_mps = {7.0, 0.0, 0.1};
    twist.omega_base_radps = {0.0, 0.02, 0.3};
    twist.covariance.topLeftCorner<3, 3>() = Eigen::Vector3d(1e-4, 4e-4, 9e-4).asDiagonal();
    // The kinematic model's roll: zero variance (paper eq. 9), as every rate here.
    PriorNoiseConfig noise;
    const double dt = 0.08;
    const MotionPrior prior = PriorFromDoppler(T0, twist, dt, noise);
    EXPECT_LT(PoseError(prior.T_world_base,
                        T0 * ExpSE3(Xi(7.0 * dt, 0, 0.1 * dt, 0, 0.02 * dt, 0.3 * dt))),
              1e-12);
    const double floor_v = noise.doppler_min_sigma_v_mps * noise.doppler_min_sigma_v_mps;
    EXPECT_NEAR(prior.covariance(1, 1), (4e-4 + floor_v) * dt * dt, 1e-15);
    // Roll is not observed by the kinematic model: it gets the floor, never zero.
    EXPECT_NEAR(prior.covariance(3, 3), std::pow(noise.doppler_min_sigma_omega_radps.x() * dt, 2),
                1e-15);
    EXPECT_GT(prior.covariance.ldlt().vectorD().minCoeff(), 0.0);
}

TEST(MotionPrior, TrapezoidTwistIntegratesAConstantAccelerationExactly) {
    // Straight line, a = 3 m/s^2 from 10 m/s over 0.1 s: the true displacement is
    // v0 dt + a dt^2 / 2 = 1.015 m. The end twist alone says v1 dt = 1.03 m (a dt^2 / 2 too far).
    const double v0 = 10.0, a = 3.0, dt = 0.1;
    Twist start, end;
    start.v_base_mps = {v0, 0.0, 0.0};
    end.v_base_mps = {v0 + a * dt, 0.0, 0.0};
    start.covariance.topLeftCorner<3, 3>() = Eigen::Vector3d(4e-4, 1e-4, 1e-4).asDiagonal();
    end.covariance.topLeftCorner<3, 3>() = Eigen::Vector3d(2e-4, 3e-4, 1e-4).asDiagonal();
    start.covariance.bottomRightCorner<3, 3>() = 1e-6 * Eigen::Matrix3d::Identity();
    end.covariance.bottomRightCorner<3, 3>() = 3e-6 * Eigen::Matrix3d::Identity();
    const double truth = v0 * dt + 0.5 * a * dt * dt;
    const PriorNoiseConfig noise;
    const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
    EXPECT_NEAR(PriorFromDoppler(I, end, dt, noise).T_world_base.translation().x() - truth,
                0.5 * a * dt * dt, 1e-12);
    const Twist mean = TrapezoidTwist(start, end);
    EXPECT_NEAR(PriorFromDoppler(I, mean, dt, noise).T_world_base.translation().x(), truth, 1e-12);
    // (C_start + C_end) / 2: consecutive intervals share a scan (the sum over n intervals).
    EXPECT_NEAR(mean.covariance(0, 0), 3e-4, 1e-18);
    EXPECT_NEAR(mean.covariance(1, 1), 2e-4, 1e-18);
    EXPECT_NEAR(mean.covariance(5, 5), 2e-6, 1e-18);
    EXPECT_STREQ(ToString(noise.doppler_integration), "trapezoid");  // the default
}

TEST(MotionPrior, ImuIntegratesConstantAccelerationAndRotationExactly) {
    // IMU rotated 90 deg about Z in the base frame, level vehicle accelerating forward at 2 m/s^2
    // while yawing at 0.5 rad/s... kept separate: first pure acceleration.
    Eigen::Isometry3d T_base_imu = Eigen::Isometry3d::Identity();
    T_base_imu.linear() = ExpSO3(Eigen::Vector3d(0, 0, M_PI / 2));
    const Eigen::Matrix3d R_imu_base = T_base_imu.linear().transpose();
    std::vector<ImuSample> samples;
    const int64_t t0 = SecondsToNanos(100.0);
    const int64_t t1 = t0 + SecondsToNanos(0.1);
    for (int k = 1; k <= 20; ++k) {
        ImuSample s;
        s.stamp_ns = t0 + k * SecondsToNanos(0.005);
        // Specific force = acceleration - gravity, in the IMU frame.
        s.accel_imu_mps2 = R_imu_base * Eigen::Vector3d(2.0, 0.0, 9.81);
        samples.push_back(s);
    }
    PriorNoiseConfig noise;
    const Eigen::Vector3d v0(5.0, 0.0, 0.0);
    auto prior =
        PriorFromImu(Eigen::Isometry3d::Identity(), v0, samples, t0, t1, T_base_imu, noise);
    ASSERT_TRUE(prior.has_value());
    // x = v0 t + a t^2 / 2.
    EXPECT_NEAR(prior->T_world_base.translation().x(), 5.0 * 0.1 + 0.5 * 2.0 * 0.01, 1e-9);
    EXPECT_NEAR(prior->T_world_base.translation().z(), 0.0, 1e-9);
    EXPECT_NEAR(RotationAngle(prior->T_world_base.linear()), 0.0, 1e-12);

    // Pure rotation at 0.5 rad/s about the base Z: the gyro reads it about the IMU's own axes.
    for (auto &s : samples) {
        s.accel_imu_mps2 = R_imu_base * Eigen::Vector3d(0.0, 0.0, 9.81);
        s.omega_imu_radps = R_imu_base * Eigen::Vector3d(0.0, 0.0, 0.5);
    }
    prior = PriorFromImu(Eigen::Isometry3d::Identity(), Eigen::Vector3d::Zero(), samples, t0, t1,
                         T_base_imu, noise);
    ASSERT_TRUE(prior.has_value());
    EXPECT_LT((LogSO3(prior->T_world_base.linear()) - Eigen::Vector3d(0, 0, 0.05)).norm(), 1e-9);
    EXPECT_LT(prior->T_world_base.translation().norm(), 1e-9);

    // No start velocity (one pose so far): the translation spreads as far as `none`'s, the
    // rotation still the gyro's.
    const auto from_unknown = PriorFromImu(Eigen::Isometry3d::Identity(), std::nullopt, samples, t0,
                                           t1, T_base_imu, noise);
    ASSERT_TRUE(from_unknown.has_value());
    EXPECT_NEAR(std::sqrt(from_unknown->covariance(0, 0)), noise.none_sigma_translation_m, 1e-12);
    EXPECT_NEAR(from_unknown->covariance(3, 3), prior->covariance(3, 3), 1e-15);
    EXPECT_LT(std::sqrt(prior->covariance(0, 0)), 0.1 * noise.none_sigma_translation_m);

    // No sample: no prior.
    EXPECT_FALSE(
        PriorFromImu(Eigen::Isometry3d::Identity(), v0, {}, t0, t1, T_base_imu, noise).has_value());
}

TEST(MotionPrior, ImuAndDopplerTakesRotationFromTheGyroAndTranslationFromDoppler) {
    Eigen::Isometry3d T_base_imu = Eigen::Isometry3d::Identity();
    T_base_imu.linear() = ExpSO3(Eigen::Vector3d(M_PI, 0, 0));  // upside down
    std::vector<ImuSample> samples(5);
    for (int k = 0; k < 5; ++k) {
        samples[k].stamp_ns = 1000 + 10 * k;
        samples[k].omega_imu_radps = Eigen::Vector3d(0.0, 0.0, -0.4);  // +0.4 about base Z
    }
    Twist twist;
    twist.covariance = Matrix6d::Identity();
    twist.v_base_mps = {6.0, 0.0, 0.0};
    twist.omega_base_radps = {0.3, 0.3, 0.3};  // ignored
    const auto prior = PriorFromImuAndDoppler(Eigen::Isometry3d::Identity(), twist, samples, 1000,
                                              1040, T_base_imu, 0.1, PriorNoiseConfig{});
    ASSERT_TRUE(prior.has_value());
    EXPECT_LT(PoseError(prior->T_world_base, ExpSE3(Xi(0.6, 0, 0, 0, 0, 0.04))), 1e-12);
}

// Two Gaussian predictions of x: N(0, 1) and N(1, 3) fuse to N(1/4, 3/4) (the product of the
// densities); the other axes, equal in both, keep their mean and halve their variance.
TEST(MotionPrior, FusedPriorsAreTheProductOfTheTwoGaussians) {
    MotionPrior a, b;
    a.covariance = Matrix6d::Identity();
    b.covariance = Matrix6d::Identity();
    b.covariance(0, 0) = 3.0;
    b.T_world_base.translation().x() = 1.0;
    a.kind = PriorKind::kDoppler;
    b.kind = PriorKind::kConstVel;
    const MotionPrior fused = FusePriors(a, b);
    EXPECT_NEAR(fused.T_world_base.translation().x(), 0.25, 1e-12);
    EXPECT_NEAR(fused.T_world_base.translation().tail<2>().norm(), 0.0, 1e-12);
    EXPECT_NEAR(fused.covariance(0, 0), 0.75, 1e-12);
    EXPECT_NEAR(fused.covariance(1, 1), 0.5, 1e-12);
    EXPECT_NEAR(fused.covariance(5, 5), 0.5, 1e-12);
    EXPECT_EQ(fused.kind, PriorKind::kDoppler);
    // A prior with no information (huge covariance) leaves the other as it was.
    b.covariance = Matrix6d::Identity() * 1e12;
    b.T_world_base = ExpSE3((Vector6d() << 0.3, 0.0, 0.0, 0.0, 0.0, 0.2).finished());
    EXPECT_LT(LogSE3(FusePriors(a, b).T_world_base).norm(), 1e-9);
}

TEST(MotionPrior, MahalanobisOfTheMeanIsZeroAndScalesWithSigma) {
    MotionPrior prior;
    prior.T_world_base = ExpSE3(Xi(1, 2, 3, 0.1, 0.2, 0.3));
    prior.covariance = Matrix6d::Identity() * 0.04;  // sigma 0.2
    EXPECT_NEAR(PriorMahalanobisSquared(prior, prior.T_world_base), 0.0, 1e-20);
    const Eigen::Isometry3d moved = prior.T_world_base * ExpSE3(Xi(0.6, 0, 0, 0, 0, 0));  // 3 sigma
    EXPECT_NEAR(PriorMahalanobisSquared(prior, moved), 9.0, 1e-9);
}

}  // namespace
}  // namespace dorado::mapping
