// YawRateCalibrator against analytic truths: a drive whose yaw is exactly v_sy / s_x_true, seen
// through registered poses with a known yaw noise; the Kalman update against its closed form; no
// update where the lever is unobservable (straight, standing) or the pose is not registered.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dorado/core/lie.hpp"
#include "dorado/odometry/kinematic_model.hpp"
#include "dorado/odometry/yaw_calibration.hpp"

namespace dorado::odometry {
namespace {

constexpr double kTrueSx = 0.7;  // the radar's effective lever [m]
constexpr double kDt = 0.1;

Eigen::Matrix3d Yaw(double psi) {
    return ExpSO3(Eigen::Vector3d(0.0, 0.0, psi));
}

YawCalibrationConfig Enabled() {
    YawCalibrationConfig config;
    config.enabled = true;
    return config;
}

struct DriveOutcome {
    double s_x_m = 0.0, sigma_m = 0.0;
    int updates = 0;
    int by_status[8] = {};
};

// A weaving drive at `speed` with yaw rate omega(t); the radar's lateral velocity is
// omega * kTrueSx exactly (eq. 3 with the true lever), the registered yaw is the exact one plus
// white noise of `yaw_noise_rad`.
template <typename Omega>
DriveOutcome Drive(double configured_s_x, double seconds, double speed, Omega omega,
                   double yaw_noise_rad = 0.003, bool registered = true,
                   YawCalibrationConfig config = Enabled()) {
    YawRateCalibrator calibrator(config, configured_s_x);
    std::mt19937 rng(3);
    std::normal_distribution<double> noise(0.0, yaw_noise_rad);
    double psi = 0.0;
    DriveOutcome out;
    const int scans = static_cast<int>(seconds / kDt);
    for (int k = 0; k < scans; ++k) {
        const double t = k * kDt;
        // The interval (t - dt, t] at its midpoint rate: psi is the integral to second order.
        const double w = k == 0 ? 0.0 : omega(t - 0.5 * kDt);
        psi += w * (k == 0 ? 0.0 : kDt);
        const YawCalibrationStep step = calibrator.AddScan(
            k == 0 ? 0.0 : kDt, w * kTrueSx, speed, registered, Yaw(psi + noise(rng)));
        out.by_status[static_cast<int>(step.status)]++;
    }
    out.s_x_m = calibrator.s_x_m();
    out.sigma_m = calibrator.sigma_s_x_m();
    out.updates = calibrator.updates();
    return out;
}

double Weave(double t) {
    return 0.4 * std::sin(2.0 * M_PI * t / 10.0);
}

TEST(YawRateCalibrator, RecoversTheTrueLeverFromAWrongStart) {
    for (const double factor : {0.7, 1.0, 1.3}) {
        const DriveOutcome out = Drive(factor * kTrueSx, 120.0, 1.5, Weave);
        EXPECT_GT(out.updates, 40) << factor;
        EXPECT_NEAR(out.s_x_m, kTrueSx, 0.01 * kTrueSx) << "configured x" << factor;
        // The reported sigma is honest: the error is within 3 sigma and sigma is not vacuous.
        EXPECT_LT(std::abs(out.s_x_m - kTrueSx), 3.0 * out.sigma_m + 1e-4) << factor;
        EXPECT_LT(out.sigma_m, 0.02 * kTrueSx) << factor;
    }
}

TEST(YawRateCalibrator, NoUpdateWhenDrivingStraight) {
    const DriveOutcome out = Drive(1.3 * kTrueSx, 60.0, 1.5, [](double) { return 0.0; });
    EXPECT_EQ(out.updates, 0);
    EXPECT_DOUBLE_EQ(out.s_x_m, 1.3 * kTrueSx);
    EXPECT_GT(out.by_status[static_cast<int>(YawCalibrationStatus::kStraight)], 0);
}

TEST(YawRateCalibrator, NoUpdateWhenStanding) {
    // Turning on the spot is not what the model describes; nor is creeping: the speed gate holds.
    const DriveOutcome out = Drive(1.3 * kTrueSx, 60.0, 0.0, Weave);
    EXPECT_EQ(out.updates, 0);
    EXPECT_DOUBLE_EQ(out.s_x_m, 1.3 * kTrueSx);
    EXPECT_GT(out.by_status[static_cast<int>(YawCalibrationStatus::kStanding)], 0);
}

TEST(YawRateCalibrator, NoUpdateWithoutRegisteredPoses) {
    // A degenerate registration's yaw is noise: with `registered` false nothing is learnt from it.
    const DriveOutcome out = Drive(1.3 * kTrueSx, 60.0, 1.5, Weave, 0.5, /*registered=*/false);
    EXPECT_EQ(out.updates, 0);
    EXPECT_DOUBLE_EQ(out.s_x_m, 1.3 * kTrueSx);
    const int warmup = out.by_status[static_cast<int>(YawCalibrationStatus::kWarmup)];
    EXPECT_NEAR(warmup, 51, 1);  // the first 5 s (the first scan has no interval)
    EXPECT_EQ(out.by_status[static_cast<int>(YawCalibrationStatus::kNotRegistered)] + warmup, 600);
}

TEST(YawRateCalibrator, DisabledDoesNothing) {
    YawCalibrationConfig config;
    config.enabled = false;
    const DriveOutcome out = Drive(1.3 * kTrueSx, 30.0, 1.5, Weave, 0.003, true, config);
    EXPECT_EQ(out.updates, 0);
    EXPECT_EQ(out.by_status[static_cast<int>(YawCalibrationStatus::kDisabled)], 300);
}

TEST(YawRateCalibrator, UpdateIsTheScalarKalmanUpdate) {
    // Closed form with g0 = 1 / 0.5 = 2, P0 = (0.2 * 2)^2, no random walk (elapsed 0):
    // h = 0.1 m, predicted 0.2 rad, measured 0.25; R = 0.01^2 + (0.05 * 0.2)^2.
    YawRateCalibrator calibrator(Enabled(), 0.5);
    const double P0 = 0.16, h = 0.1, R = 1e-4 + 1e-4;
    const double S = h * h * P0 + R, K = P0 * h / S;
    const double g = 2.0 + K * (0.25 - 0.2), P = (1.0 - K * h) * P0;
    const YawCalibrationStep step = calibrator.Update(0.25, h, 1.0, 0.0);
    ASSERT_EQ(step.status, YawCalibrationStatus::kUpdated);
    EXPECT_NEAR(step.s_x_m, 1.0 / g, 1e-12);
    EXPECT_NEAR(step.sigma_s_x_m, std::sqrt(P) / (g * g), 1e-12);
    EXPECT_NEAR(step.innovation_chi2, 0.05 * 0.05 / S, 1e-12);
}

TEST(YawRateCalibrator, RefusesAnOutlierWindow) {
    YawRateCalibrator calibrator(Enabled(), 0.5);
    // Predicted 0.2 rad, measured 2.0 rad: far beyond the gate.
    const YawCalibrationStep step = calibrator.Update(2.0, 0.1, 1.0, 0.0);
    EXPECT_EQ(step.status, YawCalibrationStatus::kOutlier);
    EXPECT_DOUBLE_EQ(step.s_x_m, 0.5);
    EXPECT_EQ(calibrator.updates(), 0);
}

TEST(YawRateCalibrator, RandomWalkWidensTheCovarianceWithTime) {
    YawCalibrationConfig config = Enabled();
    config.relative_random_walk_per_sqrt_s = 0.05;
    YawRateCalibrator a(config, 0.5), b(config, 0.5);
    (void)a.Update(0.21, 0.1, 1.0, 0.0);
    (void)b.Update(0.21, 0.1, 1.0, 100.0);  // the same window after 100 s: the prior is wider
    EXPECT_GT(std::abs(b.s_x_m() - 0.5), std::abs(a.s_x_m() - 0.5));
}

TEST(KinematicModel, YawLeverChangesOnlyTheYawRateAndItsLeverArm) {
    Extrinsics extrinsics;
    extrinsics.T_base_radar.translation() = Eigen::Vector3d(0.7, 0.1, 0.4);
    VehicleGeometry geometry;
    geometry.half_wheelbase_m = 0.256;
    KinematicModel model(extrinsics, geometry);
    const Eigen::Vector3d v_radar(1.2, 0.21, -0.03);
    const VehicleMotion before = model.Motion(v_radar, Eigen::Matrix3d::Identity() * 1e-4);
    model.SetYawLever(0.6);
    EXPECT_DOUBLE_EQ(model.yaw_lever_m(), 0.6);
    const VehicleMotion after = model.Motion(v_radar, Eigen::Matrix3d::Identity() * 1e-4);
    EXPECT_NEAR(after.omega_base_radps.z(), 0.21 / 0.6, 1e-12);
    EXPECT_NEAR(after.omega_base_radps.y(), before.omega_base_radps.y(), 1e-12);
    // v_base = v_s - omega x s with the physical s: the rear axle now slides sideways.
    const Eigen::Vector3d expected = v_radar - after.omega_base_radps.cross(Eigen::Vector3d(0.7, 0.1, 0.4));
    EXPECT_LT((after.v_base_mps - expected).norm(), 1e-12);
    EXPECT_THROW(model.SetYawLever(0.0), std::invalid_argument);
}

}  // namespace
}  // namespace dorado::odometry
