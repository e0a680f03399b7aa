// The planar twist filter against an independent truth (dorado/testing/planar_rig.hpp): radars
// on a vehicle whose twist is known at every instant, each firing at its own time, one of them
// mounted half a degree off its published yaw.
#include <gtest/gtest.h>

#include <cmath>

#include "dorado/core/angles.hpp"
#include "dorado/odometry/planar_ego_velocity.hpp"
#include "dorado/odometry/planar_twist_filter.hpp"
#include "dorado/testing/planar_rig.hpp"

namespace dorado::odometry {
namespace {

struct FilterRun {
    double yaw_rate_rms_radps = 0.0;  ///< after the first 10 s, against the truth at each stamp
    std::vector<double> offsets_deg;
    std::vector<double> sigmas_deg;
};

// 24 s (192 m); radar k fires every 1/13 s starting at k * 17 ms (never together).
FilterRun Drive(const testing::PlanarRig &rig, PlanarTwistFilterConfig config) {
    VehicleVelocityPrior prior;
    prior.enabled = true;
    prior.sigma_lateral_mps = 0.1;
    PlanarTwistFilter filter(config, prior, rig.published);
    const PlanarEgoVelocityEstimator estimator{EgoVelocityConfig{}};
    double sum = 0.0;
    int count = 0;
    uint64_t seed = 1;
    for (int i = 0; i < 13 * 24; ++i) {
        for (std::size_t k = 0; k < rig.published.size(); ++k) {
            const double t = i / 13.0 + 0.017 * static_cast<double>(k);
            const RadarScan scan = rig.Scan(k, t, seed++);
            const TwistUpdate update = filter.Update(scan.stamp_ns, k, estimator.Estimate(scan));
            EXPECT_NE(update, TwistUpdate::kRestarted) << "t " << t;
            if (t > 10.0) {
                const double e = filter.twist()(2) - rig.Twist(t)(2);
                sum += e * e;
                ++count;
            }
        }
    }
    FilterRun run;
    run.yaw_rate_rms_radps = std::sqrt(sum / count);
    for (std::size_t k = 0; k < rig.published.size(); ++k) {
        run.offsets_deg.push_back(RadToDeg(filter.mount_yaw_offset_rad(k)));
        run.sigmas_deg.push_back(RadToDeg(filter.mount_yaw_sigma_rad(k)));
    }
    return run;
}

TEST(PlanarTwistFilter, TracksTheTwistWithEachRadarAtItsOwnTime) {
    const testing::PlanarRig rig;
    PlanarTwistFilterConfig config;
    config.calibrate_mount_yaw = false;
    const FilterRun run = Drive(rig, config);
    // The yaw rate swings +-0.15 rad/s (8.6 deg/s); the filter follows it within a few 0.1 deg/s.
    EXPECT_LT(run.yaw_rate_rms_radps, 0.006) << run.yaw_rate_rms_radps;
}

TEST(PlanarTwistFilter, RecoversAMountYawOffsetFromTheOtherRadars) {
    testing::PlanarRig rig;
    rig.yaw_offset_deg = {0.0, 0.5, 0.0, -0.3};
    PlanarTwistFilterConfig fixed;
    fixed.calibrate_mount_yaw = false;
    const FilterRun with_fixed = Drive(rig, fixed);
    const FilterRun calibrated = Drive(rig, PlanarTwistFilterConfig{});
    for (std::size_t k = 0; k < rig.published.size(); ++k) {
        EXPECT_NEAR(calibrated.offsets_deg[k], rig.yaw_offset_deg[k], 0.1) << "radar " << k;
        // Its uncertainty is reported, and honest: the error within 3 sigma.
        EXPECT_LT(calibrated.sigmas_deg[k], 0.25) << "radar " << k;
        EXPECT_LT(std::abs(calibrated.offsets_deg[k] - rig.yaw_offset_deg[k]),
                  3.0 * calibrated.sigmas_deg[k])
            << "radar " << k;
        EXPECT_EQ(with_fixed.offsets_deg[k], 0.0);
    }
    // The wrong mounts bias the fixed filter's yaw rate; the calibrated one is back to the truth.
    EXPECT_LT(calibrated.yaw_rate_rms_radps, 0.5 * with_fixed.yaw_rate_rms_radps)
        << calibrated.yaw_rate_rms_radps << " vs " << with_fixed.yaw_rate_rms_radps;
}

TEST(PlanarTwistFilter, GatesARadarThatLockedOntoMoversAndRestartsWhenAllDisagree) {
    const testing::PlanarRig rig;
    PlanarTwistFilter filter(PlanarTwistFilterConfig{}, VehicleVelocityPrior{}, rig.published);
    const PlanarEgoVelocityEstimator estimator{EgoVelocityConfig{}};
    for (int i = 0; i < 40; ++i) {
        const RadarScan scan = rig.Scan(i % 4, 0.02 * i, i);
        ASSERT_NE(filter.Update(scan.stamp_ns, i % 4, estimator.Estimate(scan)),
                  TwistUpdate::kGated);
    }
    // What each radar should measure at the filter's twist is what it does measure.
    for (std::size_t k = 0; k < rig.published.size(); ++k)
        EXPECT_LT(
            (filter.RadarVelocity(k) - estimator.Estimate(rig.Scan(k, 0.78, 50 + k)).v_radar_mps)
                .norm(),
            0.05)
            << k;
    const Eigen::Vector3d before = filter.twist();
    EgoVelocityResult crowd = estimator.Estimate(rig.Scan(0, 0.8, 99));
    crowd.v_radar_mps.x() -= 6.0;  // a bus moving with the radar
    EXPECT_EQ(filter.Update(crowd.v_radar_mps.allFinite() ? 800000000 : 0, 0, crowd),
              TwistUpdate::kGated);
    EXPECT_LT((filter.twist() - before).norm(), 0.05);
    EXPECT_EQ(filter.Update(790000000, 1, crowd), TwistUpdate::kOutOfOrder);
    EgoVelocityResult invalid = crowd;
    invalid.failure = EgoVelocityFailure::kTooFewPoints;
    EXPECT_EQ(filter.Update(810000000, 1, invalid), TwistUpdate::kInvalid);
    // Ten in a row disagreeing (the one above and nine more): the vehicle is what changed, the
    // filter starts over.
    TwistUpdate last = TwistUpdate::kTaken;
    for (int i = 0; i < 9; ++i) last = filter.Update(820000000 + i * 1000000, 0, crowd);
    EXPECT_EQ(last, TwistUpdate::kRestarted);
}

TEST(PlanarTwistFilter, RefusesABadConfig) {
    PlanarTwistFilterConfig config;
    config.velocity_walk_mps = 0.0;
    EXPECT_THROW(PlanarTwistFilter(config, {}, {Eigen::Isometry3d::Identity()}),
                 std::invalid_argument);
    EXPECT_THROW(PlanarTwistFilter(PlanarTwistFilterConfig{}, {}, {}), std::invalid_argument);
}

}  // namespace
}  // namespace dorado::odometry
