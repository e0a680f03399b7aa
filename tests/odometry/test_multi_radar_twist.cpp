// The joint planar twist from several radars against an independent truth: static points seen
// by radars on a rigid body moving with a known twist (v_s = v_b + omega e_z x s per radar, each
// radar's Doppler from its own velocity in its own frame).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "dorado/core/angles.hpp"
#include "dorado/odometry/multi_radar_twist.hpp"
#include "dorado/odometry/planar_ego_velocity.hpp"

namespace dorado::odometry {
namespace {

Eigen::Isometry3d Mount(double x, double y, double yaw_deg) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() << x, y, 0.5;
    T.linear() = Eigen::AngleAxisd(DegToRad(yaw_deg), Eigen::Vector3d::UnitZ()).matrix();
    return T;
}

// A 2D scan of static points (plus 20 % movers) seen by a radar mounted at T moving with the
// base twist (v_x, v_y, omega).
RadarScan Scan(const Eigen::Isometry3d &T, const Eigen::Vector3d &twist, double sigma,
               uint64_t seed) {
    const Eigen::Vector3d s = T.translation();
    const Eigen::Vector3d v_s(twist(0) - twist(2) * s.y(), twist(1) + twist(2) * s.x(), 0.0);
    const Eigen::Vector3d v_radar = T.linear().transpose() * v_s;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> az(-1.2, 1.2), range(3.0, 70.0), off(2.0, 6.0);
    std::normal_distribution<double> noise(0.0, sigma);
    RadarScan scan;
    const int n = 120;
    scan.Resize(n);
    scan.has_power = false;
    for (int i = 0; i < n; ++i) {
        const double a = az(rng), r = range(rng);
        const Eigen::Vector3d d(std::cos(a), std::sin(a), 0.0);
        scan.xyz_radar.col(i) = r * d;
        scan.doppler_mps[i] = -d.dot(v_radar) + noise(rng) + (i % 5 == 0 ? off(rng) : 0.0);
        scan.power_db[i] = 0.0;
    }
    scan.DeriveSphericalFromXyz();
    return scan;
}

struct Rig {
    std::vector<Eigen::Isometry3d> mounts = {Mount(3.4, 0.0, 0.0), Mount(2.4, 0.9, 90.0),
                                             Mount(-0.6, 0.9, 160.0), Mount(-0.6, -0.9, -160.0),
                                             Mount(2.4, -0.9, -90.0)};
};

PlanarTwist Estimate(const Rig &rig, const Eigen::Vector3d &twist, double sigma, uint64_t seed,
                     std::size_t radars) {
    const PlanarEgoVelocityEstimator estimator{EgoVelocityConfig{}};
    std::vector<RadarScan> scans;
    std::vector<EgoVelocityResult> egos;
    for (std::size_t k = 0; k < radars; ++k) {
        scans.push_back(Scan(rig.mounts[k], twist, sigma, seed * 10 + k));
        egos.push_back(estimator.Estimate(scans.back()));
    }
    std::vector<RadarObservation> observations;
    for (std::size_t k = 0; k < radars; ++k)
        observations.push_back({&scans[k], rig.mounts[k], &egos[k]});
    return EstimatePlanarTwist(observations);
}

TEST(MultiRadarTwist, RecoversTheTwistIncludingASideslip) {
    const Eigen::Vector3d twist(12.0, 0.4, 0.25);  // a lateral velocity the Ackermann model forbids
    const PlanarTwist t = Estimate(Rig{}, twist, 0.0, 1, 5);
    ASSERT_TRUE(t.valid()) << t.failure_detail;
    EXPECT_EQ(t.radars_used, 5);
    EXPECT_LT((t.twist - twist).norm(), 1e-6) << t.twist.transpose();
}

TEST(MultiRadarTwist, CovarianceMatchesTheScatter) {
    const Eigen::Vector3d twist(8.0, 0.0, -0.3);
    double nees = 0.0;
    const int runs = 200;
    for (int k = 0; k < runs; ++k) {
        // Noise within the per-radar inlier gate (3 x 0.05 m/s): the gate does not truncate it.
        const PlanarTwist t = Estimate(Rig{}, twist, 0.04, 100 + k, 5);
        ASSERT_TRUE(t.valid()) << t.failure_detail;
        const Eigen::Vector3d e = t.twist - twist;
        nees += e.dot(t.covariance.ldlt().solve(e));
    }
    EXPECT_NEAR(nees / runs, 3.0, 0.6);  // chi-square, 3 dof
}

TEST(MultiRadarTwist, OneRadarCannotObserveTheYawRate) {
    const PlanarTwist t = Estimate(Rig{}, Eigen::Vector3d(10.0, 0.0, 0.1), 0.05, 7, 1);
    EXPECT_FALSE(t.valid());
    EXPECT_EQ(t.failure, PlanarTwistFailure::kTooFewRadars) << t.failure_detail;
}

}  // namespace
}  // namespace dorado::odometry
