// DopplerOdometry: a simulated vehicle with a known constant twist (on a hill, in a turn) must be
// integrated to its known pose T(t) = ExpSE3([v; omega] t).
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/core/time.hpp"
#include "dorado/odometry/doppler_odometry.hpp"
#include "dorado/testing/doppler_scan.hpp"

namespace dorado::odometry {
namespace {

struct Rig {
    Extrinsics extrinsics;
    VehicleGeometry geometry{0.256, KinematicModelNoise{}};
    Vector6d xi;  // true body twist [v_base; omega_base]
    Rig() {
        extrinsics.T_base_radar.linear() = (Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitZ()) *
                                            Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY()))
                                               .toRotationMatrix();
        extrinsics.T_base_radar.translation() = Eigen::Vector3d(1.0, 0.1, 0.8);
        // Climbing while turning left: omega = (0, pitch, yaw); the constraints fix v_y = 0 and
        // v_z = omega_y m (the Y-ICR point has no vertical velocity).
        const Eigen::Vector3d omega(0.0, -0.08, 0.35);
        const Eigen::Vector3d v(4.0, 0.0, omega.y() * geometry.half_wheelbase_m);
        xi << v, omega;
    }
    Eigen::Vector3d VRadar() const {
        const Eigen::Vector3d v_s =
            xi.head<3>() + xi.tail<3>().cross(extrinsics.T_base_radar.translation());
        return extrinsics.T_base_radar.linear().transpose() * v_s;
    }
    RadarScan Scan(int64_t stamp_ns, double sigma, uint64_t seed) const {
        testing::SceneOptions o;
        o.points = 800;
        o.v_radar = VRadar();
        o.doppler_sigma_mps = sigma;
        // Noise-free scans are fully static (so that the result is exact); noisy ones carry
        // 20 % moving points.
        o.dynamic_fraction = sigma > 0.0 ? 0.2 : 0.0;
        o.seed = seed;
        RadarScan scan = testing::MakeScan(o).scan;
        scan.stamp_ns = stamp_ns;
        return scan;
    }
    Eigen::Isometry3d Truth(double t_s) const { return ExpSE3(xi * t_s); }
};

double PoseError(const Eigen::Isometry3d &a, const Eigen::Isometry3d &b) {
    return (a.translation() - b.translation()).norm() +
           RotationAngle(a.linear().transpose() * b.linear());
}

TEST(DopplerOdometry, ConstantTwistOnAHillInATurnIntegratesToTheTruePose) {
    const Rig rig;
    DopplerOdometryConfig config;
    config.angular_rate_prior = false;  // eq. (5) exactly: the integration alone is under test
    DopplerOdometry odometry(config, rig.extrinsics, rig.geometry);
    // 10 Hz with jitter, scan 20 dropped: its interval must not be lost.
    int64_t t = 1'000'000'000;
    const int64_t t0 = t;
    for (int k = 0; k < 60; ++k) {
        t += 100'000'000 + (k % 3) * 7'000'000;
        if (k == 20) continue;
        const auto step = odometry.Register(rig.Scan(t, 0.0, k));
        ASSERT_TRUE(step.integrated);
        ASSERT_FALSE(step.used_fallback) << step.fallback_reason;
    }
    const double T = NanosToSeconds(t - t0);
    const Eigen::Isometry3d expected = rig.Truth(T - 0.1);  // first scan at t0 + 0.1 s
    const Eigen::Isometry3d &got = odometry.trajectory().poses().back().T_world_body;
    EXPECT_LT(PoseError(got, expected), 1e-9);
    EXPECT_GT(expected.translation().norm(), 15.0);
    EXPECT_GT(std::abs(expected.translation().z()), 0.2);  // it really climbed
}

TEST(DopplerOdometry, NoisyDopplerStaysCloseToTheTruePose) {
    const Rig rig;
    // Rotation error accumulates as a random walk of the per-scan omega errors of eq. (5):
    // var = sum dt^2 trace(C_omega) (first order, small angles). The angular-rate prior is off:
    // on this rig's steady climb (0.08 rad/s of pitch rate for 5 s) its pull towards zero is a
    // bias, not noise (AngularRatePriorTamesAMountNearTheYIcrAxis tests the prior).
    DopplerOdometryConfig config;
    config.angular_rate_prior = false;
    DopplerOdometry odometry(config, rig.extrinsics, rig.geometry);
    double rotation_var = 0.0;
    for (int k = 0; k <= 50; ++k) {
        const auto step = odometry.Register(rig.Scan(k * 100'000'000LL, 0.05, 100 + k));
        ASSERT_TRUE(step.ego.valid()) << Describe(step.ego);
        rotation_var += step.dt_s * step.dt_s * step.motion.cov_omega_base.trace();
    }
    const Eigen::Isometry3d expected = rig.Truth(5.0);
    const Eigen::Isometry3d &got = odometry.trajectory().poses().back().T_world_body;
    const double distance = 5.0 * rig.xi.head<3>().norm();
    const double error = (got.translation() - expected.translation()).norm();
    const double rotation_error = RotationAngle(got.linear().transpose() * expected.linear());
    std::printf(
        "noisy Doppler: %.3f m position error after %.1f m, %.3f deg rotation error "
        "(predicted sigma %.3f deg)\n",
        error, distance, RadToDeg(rotation_error), RadToDeg(std::sqrt(rotation_var)));
    EXPECT_LT(rotation_error, 4.0 * std::sqrt(rotation_var));
    EXPECT_LT(error, 0.03 * distance);
}

// A radar on the right flank 4.4 cm behind the Y-ICR axis, looking right, on a vehicle turning on
// flat ground: eq. (5) turns the vertical velocity noise into pitch-rate noise of tens of deg/s.
// The angular-rate prior keeps the integrated attitude sane; the translation stays close.
TEST(DopplerOdometry, AngularRatePriorTamesAMountNearTheYIcrAxis) {
    Rig rig;
    rig.extrinsics.T_base_radar.linear() = (Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitZ()) *
                                            Eigen::AngleAxisd(0.09, Eigen::Vector3d::UnitY()))
                                               .toRotationMatrix();
    rig.extrinsics.T_base_radar.translation() = Eigen::Vector3d(0.30, -0.28, 0.50);
    rig.xi << 1.0, 0.0, 0.0, 0.0, 0.0, 0.35;
    const auto run = [&](bool prior) {
        DopplerOdometryConfig config;
        config.angular_rate_prior = prior;
        config.max_angular_rate_radps = 100.0;  // keep every raw twist: the prior is under test
        DopplerOdometry odometry(config, rig.extrinsics, rig.geometry);
        for (int k = 0; k <= 50; ++k) odometry.Register(rig.Scan(k * 100'000'000LL, 0.05, 300 + k));
        const Eigen::Isometry3d &got = odometry.trajectory().poses().back().T_world_body;
        const Eigen::Isometry3d expected = rig.Truth(5.0);
        return std::make_pair(RotationAngle(got.linear().transpose() * expected.linear()),
                              (got.translation() - expected.translation()).norm());
    };
    const auto [raw_rotation, raw_translation] = run(false);
    const auto [rotation, translation] = run(true);
    std::printf("side mount, 5 s: rotation error %.2f deg raw, %.2f deg with the prior\n",
                RadToDeg(raw_rotation), RadToDeg(rotation));
    EXPECT_GT(raw_rotation, DegToRad(5.0));
    EXPECT_LT(rotation, raw_rotation / 4);
    EXPECT_LT(translation, 0.05 * 5.0);
    EXPECT_LT(translation, raw_translation);
}

TEST(DopplerOdometry, InvalidScansFallBackToTheLastTwistOverTheRealInterval) {
    const Rig rig;
    DopplerOdometryConfig config;
    config.angular_rate_prior = false;  // eq. (5) exactly, so that the pose is exact
    DopplerOdometry odometry(config, rig.extrinsics, rig.geometry);
    int64_t t = 0;
    for (int k = 0; k < 30; ++k, t += 100'000'000) {
        RadarScan scan = rig.Scan(t, 0.0, k);
        if (k == 10) scan.doppler_mps.setConstant(NAN);  // unusable scan
        if (k == 11) scan = RadarScan{}, scan.stamp_ns = t;
        const auto step = odometry.Register(scan);
        EXPECT_EQ(step.used_fallback, k == 10 || k == 11) << k;
        if (k == 10 || k == 11) {
            EXPECT_EQ(step.fallback_cause, FallbackCause::kInvalidVelocity) << k;
            EXPECT_EQ(step.ego.failure,
                      k == 10 ? EgoVelocityFailure::kTooFewPoints : EgoVelocityFailure::kEmptyScan)
                << step.fallback_reason;
        }
        if (k == 10) {  // the message: the estimator's cause with its numbers, then what was done
            EXPECT_EQ(step.fallback_reason.rfind(Describe(step.ego), 0), 0u)
                << step.fallback_reason;
        }
        EXPECT_TRUE(step.T_world_base.matrix().allFinite());
    }
    EXPECT_LT(PoseError(odometry.trajectory().poses().back().T_world_body, rig.Truth(2.9)), 1e-9);
}

TEST(DopplerOdometry, OutOfOrderStampsAreSkipped) {
    const Rig rig;
    DopplerOdometry odometry({}, rig.extrinsics, rig.geometry);
    odometry.Register(rig.Scan(200, 0.0, 1));
    const auto step = odometry.Register(rig.Scan(100, 0.0, 2));
    EXPECT_FALSE(step.integrated);
    EXPECT_NE(step.skip_reason.find("not after"), std::string::npos);
    EXPECT_EQ(odometry.trajectory().size(), 1u);
}

TEST(DopplerOdometry, ImuRotationUsesTheGyroAndImuOnlyHasNoTranslation) {
    const Rig rig;
    DopplerOdometryConfig imu_config, imu_only_config;
    imu_config.method = OdometryMethod::kImuDoppler;
    imu_only_config.method = OdometryMethod::kImu;
    DopplerOdometry imu(imu_config, rig.extrinsics, rig.geometry);
    DopplerOdometry imu_only(imu_only_config, rig.extrinsics, rig.geometry);
    // A slightly wrong s_x in the model does not matter when the rotation comes from the gyro.
    Extrinsics wrong = rig.extrinsics;
    wrong.T_base_radar.translation().x() += 0.3;
    DopplerOdometry imu_wrong_sx(imu_config, wrong, rig.geometry);
    const Eigen::Vector3d gyro = rig.xi.tail<3>();
    for (int k = 0; k <= 20; ++k) {
        const RadarScan scan = rig.Scan(k * 100'000'000LL, 0.0, k);
        imu.Register(scan, gyro);
        imu_only.Register(scan, gyro);
    }
    EXPECT_LT(PoseError(imu.trajectory().poses().back().T_world_body, rig.Truth(2.0)), 1e-9);
    const auto &only = imu_only.trajectory().poses().back().T_world_body;
    EXPECT_LT(only.translation().norm(), 1e-12);
    EXPECT_LT(RotationAngle(only.linear().transpose() * rig.Truth(2.0).linear()), 1e-9);
    // Without gyro samples kImu falls back to the Doppler rotation and says so.
    const auto step = imu.Register(rig.Scan(3'000'000'000LL, 0.0, 99));
    EXPECT_EQ(step.fallback_cause, FallbackCause::kDopplerRotation) << step.fallback_reason;
    const KinematicModel model(rig.extrinsics, rig.geometry);
    EXPECT_LT(
        (step.omega_base_used_radps - model.PlausibleTwist(step.motion).omega_base_radps).norm(),
        1e-12);
    // Eq. (5) on this noise-free scan is the truth; the plausible twist pulls its steady pitch
    // rate towards zero by the prior's weight (the model's pitch-rate noise against 0.2 rad/s).
    EXPECT_LT((step.motion.omega_base_radps - gyro).norm(), 0.02 * gyro.norm());
    EXPECT_NEAR(step.omega_base_used_radps.z(), gyro.z(), 0.02 * std::abs(gyro.z()));
    EXPECT_LT(std::abs(step.omega_base_used_radps.y()), std::abs(gyro.y()));
    EXPECT_GT(step.omega_base_used_radps.y() * gyro.y(), 0.8 * gyro.y() * gyro.y());
}

TEST(DopplerOdometry, StandingStillIntegratesNothing) {
    Rig rig;
    rig.xi.setZero();
    DopplerOdometry odometry({}, rig.extrinsics, rig.geometry);
    for (int k = 0; k < 20; ++k) {
        const auto step = odometry.Register(rig.Scan(k * 100'000'000LL, 0.05, k));
        EXPECT_TRUE(step.ego.stationary);
    }
    EXPECT_EQ(odometry.trajectory().poses().back().T_world_body.matrix(),
              Eigen::Matrix4d::Identity());
}

}  // namespace
}  // namespace dorado::odometry

namespace dorado::odometry {
namespace {

// A platform with no kinematic constraint: Doppler-only rotation is refused; with the gyro the
// twist is v_base = R v_radar - omega x s and omega = the gyro (here: the rig's true twist, exact);
// without a gyro sample the scan falls back with the cause no_imu_samples.
TEST(DopplerOdometry, UnconstrainedPlatformTakesTheRotationFromTheGyroOnly) {
    Rig rig;
    rig.extrinsics.T_base_radar.translation() = Eigen::Vector3d(0.03, -0.03, 0.06);  // hand-held
    rig.xi << 1.2, 0.3, -0.2, 0.4, -0.3, 0.9;  // any twist: nothing constrains it
    rig.geometry.model = VehicleModel::kUnconstrained;
    DopplerOdometryConfig config;
    EXPECT_THROW(DopplerOdometry(config, rig.extrinsics, rig.geometry), std::invalid_argument);
    config.method = OdometryMethod::kImuDoppler;
    DopplerOdometry odometry(config, rig.extrinsics, rig.geometry);
    const Eigen::Vector3d gyro = rig.xi.tail<3>();
    for (int k = 0; k < 10; ++k) {
        const auto step = odometry.Register(rig.Scan(k * 100'000'000, 0.0, k), gyro);
        ASSERT_FALSE(step.used_fallback) << k;
        EXPECT_LT((step.v_base_used_mps - rig.xi.head<3>()).norm(), 1e-9);
        EXPECT_LT((step.omega_base_used_radps - gyro).norm(), 1e-12);
    }
    EXPECT_LT(PoseError(odometry.trajectory().poses().back().T_world_body, rig.Truth(0.9)), 1e-9);
    const auto step = odometry.Register(rig.Scan(1'000'000'000, 0.0, 10));  // no gyro sample
    EXPECT_TRUE(step.used_fallback);
    EXPECT_EQ(step.fallback_cause, FallbackCause::kNoImuSamples);
}

}  // namespace
}  // namespace dorado::odometry
