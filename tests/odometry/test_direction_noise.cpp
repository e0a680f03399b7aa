// Direction-noise-aware ego-velocity (errors in variables) and aliased Doppler, against the
// scene's known velocity.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include "dorado/odometry/ego_velocity.hpp"
#include "dorado/testing/noisy_direction_scan.hpp"

namespace dorado::odometry {
namespace {

using testing::MakeNoisyDirectionScan;
using testing::NoisyDirectionOptions;

EgoVelocityConfig ConfigFor(const NoisyDirectionOptions &o, bool compensate) {
    EgoVelocityConfig c;
    c.doppler_sigma_mps = o.doppler_sigma_mps;
    c.sensor.azimuth_sigma_deg = o.azimuth_sigma_deg;
    c.sensor.elevation_sigma_deg = o.elevation_sigma_deg;
    c.sensor.doppler_unambiguous_mps = o.doppler_unambiguous_mps;
    c.compensate_direction_noise = compensate;
    return c;
}

struct MonteCarlo {
    Eigen::Vector3d mean_error = Eigen::Vector3d::Zero();
    double nees = 0.0;  // mean of e^T P^-1 e (3 when P is honest)
    int valid = 0;
};

MonteCarlo RunTrials(NoisyDirectionOptions o, bool compensate, int trials) {
    EgoVelocityEstimator estimator(ConfigFor(o, compensate));
    MonteCarlo mc;
    for (int t = 0; t < trials; ++t) {
        o.seed = 1000 + t;
        const EgoVelocityResult r = estimator.Estimate(MakeNoisyDirectionScan(o).scan);
        if (!r.valid()) continue;
        const Eigen::Vector3d e = r.v_radar_mps - o.v_radar;
        mc.mean_error += e;
        mc.nees += e.dot(r.cov_v_radar.ldlt().solve(e));
        ++mc.valid;
    }
    mc.mean_error /= mc.valid;
    mc.nees /= mc.valid;
    return mc;
}

// 12 m/s, 2 deg elevation noise, 70 % of the returns below the horizon: plain least squares pulls
// v_z down by about sigma_el^2 * v_x * mean(sin el cos el) / mean(sin^2 el) ~ 0.03 m/s; the
// compensated fit's bias is within the Monte-Carlo noise (400 scans: sigma_vz / 20 ~ 0.002).
TEST(DirectionNoise, RemovesTheVerticalBiasAtCarSpeed) {
    NoisyDirectionOptions o;
    o.v_radar = Eigen::Vector3d(12.0, 0.5, 0.0);
    const MonteCarlo plain = RunTrials(o, false, 400);
    const MonteCarlo compensated = RunTrials(o, true, 400);
    ASSERT_EQ(compensated.valid, 400);
    EXPECT_LT(plain.mean_error.z(), -0.015);  // the bias the issue measured is there
    EXPECT_LT(std::abs(compensated.mean_error.z()), 0.001 * 12.0);
    EXPECT_LT(std::abs(compensated.mean_error.x()), 0.001 * 12.0);
    EXPECT_LT(std::abs(compensated.mean_error.y()), 0.001 * 12.0);
}

// The covariance describes the real scatter, direction noise included: NEES ~ 3. The plain
// fit's covariance, from the residuals, is also consistent in size but not in its mean.
TEST(DirectionNoise, CovarianceIsHonest) {
    NoisyDirectionOptions o;
    o.v_radar = Eigen::Vector3d(8.0, -1.0, 0.2);
    const MonteCarlo mc = RunTrials(o, true, 400);
    EXPECT_GT(mc.nees, 2.6);
    EXPECT_LT(mc.nees, 3.5);
}

// Without direction noise the compensated path is plain least squares: nothing changes.
TEST(DirectionNoise, NoNoiseNoChange) {
    NoisyDirectionOptions o;
    o.azimuth_sigma_deg = o.elevation_sigma_deg = 0.0;
    const auto scan = MakeNoisyDirectionScan(o).scan;
    EgoVelocityEstimator a(ConfigFor(o, true)), b(ConfigFor(o, false));
    const EgoVelocityResult ra = a.Estimate(scan), rb = b.Estimate(scan);
    ASSERT_TRUE(ra.valid());
    EXPECT_FALSE(ra.direction_noise_compensated);
    EXPECT_EQ((ra.v_radar_mps - rb.v_radar_mps).norm(), 0.0);
}

// 14 m/s with an unambiguous velocity of 11.5 m/s: the returns ahead (|doppler| > 11.5) wrap to
// the other end of the range. With the key the estimator unwraps them and says how many; without
// it they are outliers and the velocity rests on the side returns only.
TEST(DopplerAmbiguity, AliasedScanGivesTheRightVelocity) {
    NoisyDirectionOptions o;
    o.v_radar = Eigen::Vector3d(14.0, 0.6, -0.1);
    o.azimuth_sigma_deg = o.elevation_sigma_deg = 0.0;
    o.doppler_unambiguous_mps = 11.5;
    o.seed = 7;
    const RadarScan scan = MakeNoisyDirectionScan(o).scan;
    int aliased = 0;
    for (Eigen::Index i = 0; i < scan.size(); ++i)
        aliased += scan.doppler_mps[i] > 0.0;  // static returns all approach: > 0 = wrapped
    ASSERT_GT(aliased, 200);

    EgoVelocityEstimator with_key(ConfigFor(o, true));
    const EgoVelocityResult r = with_key.Estimate(scan);
    ASSERT_TRUE(r.valid()) << Describe(r);
    EXPECT_LT((r.v_radar_mps - o.v_radar).norm(), 0.02);
    EXPECT_NEAR(r.unwrapped, aliased, 0.01 * aliased + 1);  // a 3-sigma gate loses ~0.3 %
    EXPECT_GT(r.inliers, 0.98 * static_cast<double>(scan.size()));

    NoisyDirectionOptions no_key = o;
    no_key.doppler_unambiguous_mps = 0.0;
    EgoVelocityEstimator without_key(ConfigFor(no_key, true));
    const EgoVelocityResult r0 = without_key.Estimate(scan);
    EXPECT_EQ(r0.unwrapped, 0);
    // One of the two groups (raw or wrapped) at most: far from every point.
    EXPECT_LT(r0.inliers, 0.9 * static_cast<double>(scan.size()));
}

// Aliasing and direction noise together, at 13 m/s.
TEST(DopplerAmbiguity, AliasedAndNoisyDirections) {
    NoisyDirectionOptions o;
    o.v_radar = Eigen::Vector3d(13.0, 0.0, 0.0);
    o.doppler_unambiguous_mps = 11.5;
    const MonteCarlo mc = RunTrials(o, true, 100);
    EXPECT_EQ(mc.valid, 100);
    EXPECT_LT(mc.mean_error.norm(), 0.002 * 13.0);
}

TEST(DirectionNoise, RejectsNonsenseSensorKeys) {
    EgoVelocityConfig c;
    c.sensor.elevation_sigma_deg = -1.0;
    EXPECT_THROW(c.Validate(), std::invalid_argument);
    c = EgoVelocityConfig{};
    c.sensor.doppler_unambiguous_mps = 0.2;  // narrower than the inlier gate
    EXPECT_THROW(c.Validate(), std::invalid_argument);
}

}  // namespace
}  // namespace dorado::odometry
