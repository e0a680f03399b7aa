// The mapper in planar mode (a 2D radar) against an independent truth: a car drives a circle in
// a 2-D world of walls and poles seen by a radar with no elevation (every z = 0); its Doppler
// prior has a yaw-rate bias (the single radar's lever-arm problem). Registered in the plane, the
// poses follow the truth where the prior drifts, and z, roll and pitch stay exactly the start's.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/mapping/radar_mapper.hpp"
#include "dorado/testing/mapper_input.hpp"

namespace dorado::mapping {
namespace {
using testing::PriorInput;

constexpr double kMountHeight = 0.5;

// Walls (points every 0.4 m along segments) and poles around a circle of radius 100 m.
Eigen::Matrix3Xd World(std::mt19937 &rng) {
    std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI), radius(70.0, 130.0),
        length(5.0, 25.0);
    std::vector<Eigen::Vector3d> pts;
    for (int w = 0; w < 120; ++w) {
        const double a = angle(rng), r = radius(rng), heading = angle(rng), L = length(rng);
        const Eigen::Vector2d c(r * std::cos(a), r * std::sin(a) + 100.0);
        const Eigen::Vector2d dir(std::cos(heading), std::sin(heading));
        for (double s = 0.0; s <= L; s += 0.4)
            pts.emplace_back((c + s * dir).x(), (c + s * dir).y(), kMountHeight);
    }
    Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(pts.size()));
    for (std::size_t i = 0; i < pts.size(); ++i) out.col(static_cast<Eigen::Index>(i)) = pts[i];
    return out;
}

Eigen::Isometry3d Mount() {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() << 3.5, 0.0, kMountHeight;
    return T;
}

// The world seen by the 2D radar at T_world_base: within 60 m and +-75 deg, in the radar frame,
// with 5 cm of position noise (z stays exactly 0: no elevation).
RadarScan Scan(const Eigen::Matrix3Xd &world, const Eigen::Isometry3d &T_world_base,
               std::mt19937 &rng) {
    std::normal_distribution<double> noise(0.0, 0.05);
    const Eigen::Isometry3d T_radar_world = (T_world_base * Mount()).inverse();
    std::vector<Eigen::Vector3d> seen;
    for (Eigen::Index i = 0; i < world.cols(); ++i) {
        Eigen::Vector3d p = T_radar_world * world.col(i);
        const double r = p.head<2>().norm();
        if (r < 2.0 || r > 60.0 || std::abs(std::atan2(p.y(), p.x())) > DegToRad(75.0)) continue;
        p.x() += noise(rng);
        p.y() += noise(rng);
        p.z() = 0.0;
        seen.push_back(p);
    }
    RadarScan scan;
    scan.Resize(static_cast<Eigen::Index>(seen.size()));
    for (std::size_t i = 0; i < seen.size(); ++i) {
        scan.xyz_radar.col(static_cast<Eigen::Index>(i)) = seen[i];
        scan.doppler_mps[static_cast<Eigen::Index>(i)] = 0.0;
        scan.power_db[static_cast<Eigen::Index>(i)] = 0.0;
    }
    scan.has_power = false;
    scan.DeriveSphericalFromXyz();
    return scan;
}

// One scan's input: the prior and the interval, no masks.
TEST(PlanarMapper, RegistrationInThePlaneRemovesTheYawRateBiasAndHoldsZRollPitch) {
    std::mt19937 rng(5);
    const Eigen::Matrix3Xd world = World(rng);
    const double v = 10.0, omega = 0.1, dt = 0.1, bias = 0.02;  // rad/s of yaw-rate bias
    const int scans = 150;                                      // 150 m, 86 deg of turn
    Vector6d xi;
    xi << v * dt, 0.0, 0.0, 0.0, 0.0, omega * dt;
    Extrinsics extrinsics;
    extrinsics.T_base_radar = Mount();
    RadarMapper mapper(MapperConfig{}, extrinsics);
    mapper.SetPlanar();
    Twist twist;  // the biased Doppler-odometry twist, planar covariance
    twist.v_base_mps << v, 0.0, 0.0;
    twist.omega_base_radps << 0.0, 0.0, omega + bias;
    twist.covariance.topLeftCorner<3, 3>() =
        Eigen::Vector3d(0.05 * 0.05, 0.02 * 0.02, 0.0).asDiagonal();
    twist.covariance.bottomRightCorner<3, 3>() =
        Eigen::Vector3d(0.0, 0.0, 0.01 * 0.01).asDiagonal();
    Eigen::Isometry3d truth = Eigen::Isometry3d::Identity(), prior_only = truth, estimate = truth;
    int fallbacks = 0;
    for (int k = 0; k < scans; ++k) {
        if (k > 0) truth = truth * ExpSE3(xi);
        MotionPrior prior;
        if (k == 0) {
            prior.T_world_base = truth;
            prior.covariance = Matrix6d::Identity() * 1e-6;
        } else {
            prior = PriorFromDoppler(estimate, twist, dt, PriorNoiseConfig{});
            prior_only = PriorFromDoppler(prior_only, twist, dt, PriorNoiseConfig{}).T_world_base;
        }
        const RegistrationResult r =
            mapper.Register(Scan(world, truth, rng), PriorInput(prior, dt));
        fallbacks += r.fallback();
        estimate = r.T_world_base;
        // Held: z, roll and pitch are the start's (0) exactly, to rounding.
        ASSERT_NEAR(estimate.translation().z(), 0.0, 1e-9) << k;
        ASSERT_NEAR(estimate.linear()(2, 2), 1.0, 1e-12) << k;
    }
    auto yaw_error = [&](const Eigen::Isometry3d &T) {
        return std::abs(RollPitchYaw(truth.linear().transpose() * T.linear()).z());
    };
    // The prior alone: 0.02 rad/s for 14.9 s = 0.30 rad of yaw.
    EXPECT_GT(yaw_error(prior_only), 0.25);
    EXPECT_LT(yaw_error(estimate), 0.02) << yaw_error(estimate);
    EXPECT_LT((estimate.translation() - truth.translation()).norm(),
              0.1 * (prior_only.translation() - truth.translation()).norm());
    EXPECT_LT((estimate.translation() - truth.translation()).norm(), 0.015 * v * dt * scans);
    EXPECT_LE(fallbacks, scans / 10);
}

TEST(PlanarMapper, AGyroPriorsRollAndPitchDoNotLeaveThePlane) {
    // An IMU prior on a car: the gyro's x and y rates (body roll, pitching, their noise) are
    // integrated into the prior's rotation. The 2D radar's map keeps x, y and yaw only: every pose
    // stays level (z, roll, pitch of the start) and the yaw is the prior's rotation about z.
    std::mt19937 rng(7);
    const Eigen::Matrix3Xd world = World(rng);
    const double v = 10.0, omega = 0.1, dt = 0.1;
    Vector6d xi_true, xi_gyro;
    xi_true << v * dt, 0.0, 0.0, 0.0, 0.0, omega * dt;
    xi_gyro << v * dt, 0.0, 0.0, 0.04 * dt, -0.03 * dt, omega * dt;  // + roll and pitch rates
    Extrinsics extrinsics;
    extrinsics.T_base_radar = Mount();
    RadarMapper mapper(MapperConfig{}, extrinsics);
    mapper.SetPlanar();
    Eigen::Isometry3d truth = Eigen::Isometry3d::Identity(), estimate = truth;
    for (int k = 0; k < 40; ++k) {
        if (k > 0) truth = truth * ExpSE3(xi_true);
        MotionPrior prior{estimate * ExpSE3(xi_gyro), Matrix6d::Identity() * 1e-4, PriorKind::kImu};
        if (k == 0) prior = MotionPrior{truth, Matrix6d::Identity() * 1e-6, PriorKind::kImu};
        const RegistrationResult r =
            mapper.Register(Scan(world, truth, rng), PriorInput(prior, dt));
        estimate = r.T_world_base;
        ASSERT_NEAR(estimate.translation().z(), 0.0, 1e-9) << k;
        ASSERT_NEAR(estimate.linear()(2, 2), 1.0, 1e-12) << k;
    }
    EXPECT_LT(std::abs(RollPitchYaw(truth.linear().transpose() * estimate.linear()).z()), 0.01);
    EXPECT_LT((estimate.translation() - truth.translation()).norm(), 0.5);
}

}  // namespace
}  // namespace dorado::mapping
