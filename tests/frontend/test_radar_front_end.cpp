// RadarFrontEnd on synthetic radar scans of a known drive: the map's `doppler` prior is the
// odometry's twist with every odometry setting (angular-rate prior, angular-rate limit,
// zero-velocity update), substitutions are reported, and odometry-only mode is DopplerOdometry.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <string>
#include <vector>

#include "dorado/core/lie.hpp"
#include "dorado/frontend/radar_front_end.hpp"
#include "dorado/odometry/kinematic_model.hpp"
#include "dorado/testing/street_scene.hpp"

namespace dorado::frontend {
namespace {

using mapping::PriorKind;
using testing::MakeDrive;
using testing::MakeStreetWorld;
using testing::RadarSimOptions;
using testing::SimulateScan;
using testing::TruthSample;

constexpr int64_t kDtNs = 100'000'000;  // 10 Hz

Extrinsics Mount() {
    Extrinsics e;
    e.T_base_radar.translation() = Eigen::Vector3d(1.8, 0.1, 1.2);
    e.T_base_radar.linear() = ExpSO3(Eigen::Vector3d(0.0, 0.0, 0.15));
    return e;
}

VehicleGeometry Geometry() {
    VehicleGeometry g;
    g.half_wheelbase_m = 1.4;
    return g;
}

// Scans of the street drive (static world, no movers), stamped at 10 Hz.
std::vector<RadarScan> DriveScans(int count, bool stationary = false) {
    static const Eigen::Matrix3Xd world = MakeStreetWorld(3);
    std::vector<TruthSample> truth = MakeDrive(count, 0.1);
    std::mt19937 rng(7);
    RadarSimOptions sim;
    sim.points_per_scan = 1500;
    sim.ghost_fraction = 0.0;
    std::vector<RadarScan> scans;
    for (int k = 0; k < count; ++k) {
        const Eigen::Vector3d v = stationary ? Eigen::Vector3d::Zero() : truth[k].v_base;
        const Eigen::Vector3d w = stationary ? Eigen::Vector3d::Zero() : truth[k].omega_base;
        RadarScan scan = SimulateScan(
            world, stationary ? truth[0].T_world_base : truth[k].T_world_base, Mount().T_base_radar,
            v, w, Eigen::Matrix3Xd(3, 0), Eigen::Vector3d::Zero(), sim, rng, nullptr);
        scan.stamp_ns = 1'000'000'000 + k * kDtNs;
        scans.push_back(std::move(scan));
    }
    return scans;
}

std::vector<FrontEndResult> RunFrontEnd(const FrontEndConfig &config,
                                        const std::vector<RadarScan> &scans) {
    RadarFrontEnd front_end(config, Mount(), Geometry());
    std::vector<FrontEndResult> results;
    for (const RadarScan &scan : scans) results.push_back(front_end.Process(scan));
    return results;
}

double TranslationGap(const Eigen::Isometry3d &a, const Eigen::Isometry3d &b) {
    return (a.translation() - b.translation()).norm();
}

// A scan with few points gives a Doppler twist with a wide covariance: the doppler prior then
// leans on the constvel prediction of the last two poses (prior.doppler_with_constvel), and
// its rotation is as certain as that prediction, not as the few points.
TEST(RadarFrontEnd, ADopplerPriorFromFewPointsLeansOnTheLastMotion) {
    std::vector<RadarScan> scans = DriveScans(8);
    Eigen::Array<bool, Eigen::Dynamic, 1> keep =
        Eigen::Array<bool, Eigen::Dynamic, 1>::Constant(scans[6].size(), false);
    for (Eigen::Index i = 0; i < keep.size(); i += keep.size() / 14) keep(i) = true;
    scans[6] = SelectPoints(scans[6], keep);
    double rotation_variance[2] = {0.0, 0.0};
    for (const bool fuse : {false, true}) {
        FrontEndConfig config;
        config.prior_noise.doppler_with_constvel = fuse;
        const std::vector<FrontEndResult> results = RunFrontEnd(config, scans);
        ASSERT_TRUE(results[6].odometry.ego.valid()) << results[6].odometry.ego.failure_detail;
        EXPECT_EQ(results[6].prior_used, PriorKind::kDoppler);
        rotation_variance[fuse] = results[6].prior.covariance.bottomRightCorner<3, 3>().trace();
    }
    // The angular-rate prior already caps the roll and pitch rates' variance of the Doppler
    // prior (0.2 rad/s): the fusion with the last motion removes at least a third of the rest.
    EXPECT_LT(rotation_variance[1], 0.67 * rotation_variance[0])
        << rotation_variance[1] << " vs " << rotation_variance[0];
}

TEST(RadarFrontEnd, DopplerPriorFollowsTheAngularRatePriorSetting) {
    const auto scans = DriveScans(8);
    const odometry::KinematicModel model(Mount(), Geometry());
    double largest_difference = 0.0;
    std::vector<Eigen::Vector3d> omega_by_setting[2];
    for (const bool angular_rate_prior : {false, true}) {
        FrontEndConfig config;
        config.odometry.angular_rate_prior = angular_rate_prior;
        // This scan's twist alone (the trapezoid's is checked below), not fused with constvel.
        config.prior_noise.doppler_integration = mapping::TwistIntegration::kEndpoint;
        config.prior_noise.doppler_with_constvel = false;
        const auto results = RunFrontEnd(config, scans);
        for (std::size_t k = 1; k < results.size(); ++k) {
            const FrontEndResult &r = results[k];
            ASSERT_TRUE(r.accepted);
            ASSERT_TRUE(r.odometry.ego.valid()) << k;
            ASSERT_EQ(r.prior_used, PriorKind::kDoppler) << ToString(r.prior_substitution);
            // Independently: eq. (5) from this scan's radar velocity, or its plausible twist.
            const odometry::VehicleMotion motion =
                model.Motion(r.odometry.ego.v_radar_mps, r.odometry.ego.cov_v_radar);
            Eigen::Vector3d v = motion.v_base_mps, w = motion.omega_base_radps;
            if (angular_rate_prior) {
                const Twist plausible = model.PlausibleTwist(motion);
                v = plausible.v_base_mps;
                w = plausible.omega_base_radps;
            }
            Vector6d xi;
            xi << v * 0.1, w * 0.1;
            const Eigen::Isometry3d expected = results[k - 1].T_world_base * ExpSE3(xi);
            EXPECT_LT(TranslationGap(r.prior.T_world_base, expected), 1e-9) << k;
            EXPECT_LT(RotationAngle(r.prior.T_world_base.linear().transpose() * expected.linear()),
                      1e-9)
                << k;
            omega_by_setting[angular_rate_prior].push_back(w);
        }
    }
    for (std::size_t k = 0; k < omega_by_setting[0].size(); ++k)
        largest_difference =
            std::max(largest_difference, (omega_by_setting[0][k] - omega_by_setting[1][k]).norm());
    EXPECT_GT(largest_difference, 1e-6) << "the setting changed nothing: the test cannot tell";
}

// The default trapezoid twist: the mean of the previous and this scan's twists (the odometry's,
// read back from the results) held over the interval; the second scan, without a previous
// interval, and a scan after a gap hold their own.
TEST(RadarFrontEnd, DopplerPriorHoldsTheMeanOfTheTwoScansTwists) {
    auto scans = DriveScans(8);
    for (std::size_t k = 6; k < scans.size(); ++k) scans[k].stamp_ns += 300000000;  // 0.3 s gap
    FrontEndConfig config;
    config.prior_noise.doppler_with_constvel = false;  // the twists alone
    ASSERT_EQ(config.prior_noise.doppler_integration, mapping::TwistIntegration::kTrapezoid);
    const auto results = RunFrontEnd(config, scans);
    for (std::size_t k = 1; k < results.size(); ++k) {
        const FrontEndResult &r = results[k];
        ASSERT_EQ(r.prior_used, PriorKind::kDoppler) << ToString(r.prior_substitution);
        const bool own = k == 1 || k == 6;  // no previous interval; after the gap
        const FrontEndResult &previous = results[k - 1];
        const Eigen::Vector3d v =
            own ? r.twist_base.v_base_mps
                : Eigen::Vector3d(0.5 * (previous.twist_base.v_base_mps + r.twist_base.v_base_mps));
        const Eigen::Vector3d w =
            own ? r.twist_base.omega_base_radps
                : Eigen::Vector3d(
                      0.5 * (previous.twist_base.omega_base_radps + r.twist_base.omega_base_radps));
        Vector6d xi;
        xi << v * r.dt_s, w * r.dt_s;
        const Eigen::Isometry3d expected = previous.T_world_base * ExpSE3(xi);
        EXPECT_LT(TranslationGap(r.prior.T_world_base, expected), 1e-9) << k;
        EXPECT_LT(RotationAngle(r.prior.T_world_base.linear().transpose() * expected.linear()),
                  1e-9)
            << k;
        if (!own) {  // the two scans' twists differ: the test can tell the rules apart
            EXPECT_GT((previous.twist_base.omega_base_radps - r.twist_base.omega_base_radps).norm(),
                      1e-6)
                << k;
        }
    }
}

TEST(RadarFrontEnd, DopplerPriorObeysTheAngularRateLimit) {
    const auto scans = DriveScans(8);
    FrontEndConfig config;
    int substituted_default = 0, substituted_strict = 0;
    for (const auto &r : RunFrontEnd(config, scans))
        substituted_default += r.prior_used != PriorKind::kDoppler && !r.prior_first_scan;
    // A limit below every yaw rate of the drive: each twist is implausible, the prior says so.
    config.odometry.max_angular_rate_radps = 1e-4;
    for (const auto &r : RunFrontEnd(config, scans)) {
        if (r.prior_first_scan) continue;
        EXPECT_EQ(r.prior_used, PriorKind::kConstVel);
        EXPECT_EQ(r.prior_substitution, PriorSubstitution::kAngularRateLimit);
        substituted_strict += r.prior_used == PriorKind::kConstVel;
    }
    EXPECT_EQ(substituted_default, 0);
    EXPECT_EQ(substituted_strict, 7);
}

// A scan without a valid Doppler velocity and a scan whose twist jumps: constvel stands in for
// the doppler prior, each with its own cause; the scans around them keep the doppler prior.
TEST(RadarFrontEnd, DopplerPriorSubstitutionsNameTheirCause) {
    auto scans = DriveScans(10);
    scans[3].doppler_mps.setConstant(NAN);  // no point left for the ego-velocity
    {  // scan 7 as if the vehicle drove 5 m/s faster (a RANSAC locked onto a crowd)
        const std::vector<TruthSample> truth = MakeDrive(10, 0.1);
        std::mt19937 rng(11);
        RadarSimOptions sim;
        sim.points_per_scan = 1500;
        sim.ghost_fraction = 0.0;
        scans[7] =
            SimulateScan(MakeStreetWorld(3), truth[7].T_world_base, Mount().T_base_radar,
                         truth[7].v_base + Eigen::Vector3d(5.0, 0.0, 0.0), truth[7].omega_base,
                         Eigen::Matrix3Xd(3, 0), Eigen::Vector3d::Zero(), sim, rng, nullptr);
        scans[7].stamp_ns = 1'000'000'000 + 7 * kDtNs;
    }
    const auto results = RunFrontEnd(FrontEndConfig{}, scans);
    for (std::size_t k = 1; k < results.size(); ++k) {
        const FrontEndResult &r = results[k];
        const PriorSubstitution expected = k == 3   ? PriorSubstitution::kInvalidDopplerVelocity
                                           : k == 7 ? PriorSubstitution::kDiscontinuousTwist
                                                    : PriorSubstitution::kNone;
        EXPECT_EQ(r.prior_substitution, expected) << k << ": " << ToString(r.prior_substitution);
        EXPECT_EQ(r.prior_used,
                  expected == PriorSubstitution::kNone ? PriorKind::kDoppler : PriorKind::kConstVel)
            << k;
        EXPECT_EQ(r.doppler_twist_discontinuous, k == 7) << k;
    }
    // The count key names the ego-velocity's cause, without numbers; the detail has them.
    EXPECT_EQ(results[3].odometry.ego.failure, odometry::EgoVelocityFailure::kTooFewPoints);
    EXPECT_EQ(SubstitutionKey(SubstitutionCauseOf(results[3])),
              "doppler: too few points after the pre-filters");
    EXPECT_EQ(results[3].prior_substitution_detail, "0 < min_points 10");
    EXPECT_EQ(SubstitutionKey(SubstitutionCauseOf(results[7])),
              "doppler: twist discontinuous with the previous one");
    EXPECT_EQ(results[7].static_mask.size(), scans[7].size());  // valid, but not the map's mask
}

// Each substitution cause (with each ego-velocity cause) counts under its own key, without
// numbers: summary.json's prior_substitutions_constvel and scans.csv use these keys.
TEST(RadarFrontEnd, SubstitutionKeysAreDistinct) {
    std::set<std::string> keys;
    int causes = 0;
    for (PriorSubstitution cause : kAllPriorSubstitutions) {
        for (odometry::EgoVelocityFailure ego : odometry::kAllEgoVelocityFailures) {
            const bool with_ego = cause == PriorSubstitution::kInvalidDopplerVelocity;
            if (with_ego == (ego == odometry::EgoVelocityFailure::kNone)) continue;
            const std::string key = SubstitutionKey({cause, ego});
            EXPECT_EQ(key.empty(), cause == PriorSubstitution::kNone);
            EXPECT_EQ(key.find_first_of("0123456789"), std::string::npos) << key;
            keys.insert(key);
            ++causes;
        }
    }
    EXPECT_EQ(static_cast<int>(keys.size()), causes);
}

TEST(RadarFrontEnd, DopplerPriorHoldsStillOnStationaryScans) {
    const auto scans = DriveScans(5, /*stationary=*/true);
    for (const bool zero_velocity_update : {true, false}) {
        FrontEndConfig config;
        config.odometry.zero_velocity_update = zero_velocity_update;
        config.prior_noise.doppler_integration = mapping::TwistIntegration::kEndpoint;
        config.prior_noise.doppler_with_constvel = false;  // the twist alone, integrated
        const auto results = RunFrontEnd(config, scans);
        for (std::size_t k = 1; k < results.size(); ++k) {
            const FrontEndResult &r = results[k];
            ASSERT_TRUE(r.odometry.ego.stationary) << "speed " << r.odometry.ego.v_radar_mps.norm();
            const double moved = TranslationGap(r.prior.T_world_base, results[k - 1].T_world_base);
            if (zero_velocity_update) {
                EXPECT_EQ(moved, 0.0) << k;
                EXPECT_EQ(r.twist_base.v_base_mps.norm(), 0.0);
            } else {
                // The measured (noisy, tiny) velocity is integrated instead.
                EXPECT_GT(moved, 1e-7) << k;
                EXPECT_NEAR(moved, 0.1 * r.twist_base.v_base_mps.norm(),
                            1e-6);  // ExpSE3: V(w) v dt
            }
        }
    }
}

TEST(RadarFrontEnd, ImuDopplerPriorUsesTheGyroOrSaysWhyNot) {
    const auto scans = DriveScans(4);
    const auto truth = MakeDrive(4, 0.1);
    FrontEndConfig config;
    config.prior = PriorKind::kImuDoppler;
    {  // no IMU: constvel stands in, with the reason
        const auto results = RunFrontEnd(config, scans);
        for (std::size_t k = 1; k < results.size(); ++k) {
            EXPECT_EQ(results[k].prior_used, PriorKind::kConstVel);
            EXPECT_EQ(results[k].prior_substitution, PriorSubstitution::kNoImuSamples);
            EXPECT_EQ(SubstitutionKey(SubstitutionCauseOf(results[k])), "no imu samples");
        }
    }
    RadarFrontEnd front_end(config, Mount(), Geometry());  // IMU frame = base frame
    for (std::size_t k = 0; k < scans.size(); ++k) {
        for (int j = 1; j <= 10 && k > 0; ++j) {
            ImuSample s;
            s.stamp_ns = scans[k - 1].stamp_ns + j * kDtNs / 10;
            s.omega_imu_radps = truth[k - 1].omega_base;
            s.accel_imu_mps2 = Eigen::Vector3d(0.0, 0.0, 9.81);
            front_end.AddImu(s);
        }
        const FrontEndResult r = front_end.Process(scans[k]);
        if (k == 0) continue;
        EXPECT_EQ(r.prior_used, PriorKind::kImuDoppler) << ToString(r.prior_substitution);
        EXPECT_LT((r.gyro_base_radps - truth[k - 1].omega_base).norm(), 1e-12);
        EXPECT_LT((r.twist_base.omega_base_radps - truth[k - 1].omega_base).norm(), 1e-12);
    }
}

TEST(RadarFrontEnd, StampsOutOfOrderAreSkippedAndReset) {
    auto scans = DriveScans(4);
    FrontEndConfig config;
    RadarFrontEnd front_end(config, Mount(), Geometry());
    EXPECT_TRUE(front_end.Process(scans[0]).accepted);
    EXPECT_TRUE(front_end.Process(scans[1]).accepted);
    const FrontEndResult repeated = front_end.Process(scans[1]);
    EXPECT_FALSE(repeated.accepted);
    EXPECT_NE(repeated.skip_reason.find("is not after the previous scan's"), std::string::npos);
    EXPECT_TRUE(repeated.registration.written.empty());
    // After a reset the next scan starts a new map at the given pose, with no prior; the reset
    // writes the old map's poses still in its smoother: one per accepted scan, in order.
    Eigen::Isometry3d T_start = Eigen::Isometry3d::Identity();
    T_start.translation() = Eigen::Vector3d(100.0, 0.0, 0.0);
    const std::vector<mapping::WrittenPose> flushed = front_end.Reset(T_start);
    ASSERT_EQ(flushed.size(), 2u);
    EXPECT_EQ(flushed[0].stamp_ns, scans[0].stamp_ns);
    EXPECT_EQ(flushed[1].stamp_ns, scans[1].stamp_ns);
    EXPECT_EQ(front_end.trajectory().size(), 2u);
    EXPECT_FALSE(front_end.Process(scans[1]).accepted);  // still not after the last pose
    const FrontEndResult first = front_end.Process(scans[2]);
    ASSERT_TRUE(first.accepted);
    EXPECT_TRUE(first.prior_first_scan);
    EXPECT_TRUE(first.registration.first_scan);
    EXPECT_LT(TranslationGap(first.T_world_base, T_start), 1e-12);
    EXPECT_LT(TranslationGap(first.T_world_base_odometry, T_start), 1e-12);
}

TEST(RadarFrontEnd, OdometryOnlyIsTheDopplerOdometry) {
    const auto scans = DriveScans(6);
    FrontEndConfig config;
    config.run_mapper = false;
    const auto results = RunFrontEnd(config, scans);
    odometry::DopplerOdometry odometry(config.odometry, Mount(), Geometry());
    for (std::size_t k = 0; k < scans.size(); ++k) {
        const odometry::OdometryStep step = odometry.Register(scans[k]);
        EXPECT_LT(TranslationGap(results[k].T_world_base, step.T_world_base), 1e-12);
        EXPECT_LT(TranslationGap(results[k].T_world_base_odometry, step.T_world_base), 1e-12);
        EXPECT_EQ(results[k].static_mask.size(), scans[k].size());
    }
}

}  // namespace
}  // namespace dorado::frontend
