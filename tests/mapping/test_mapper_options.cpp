// Mapper settings whose doc promises a behaviour, checked on the synthetic street against the
// numbers the doc implies: the keyframe rule (the map is updated only after keyframe_distance_m or
// keyframe_angle_deg since the last update; 0 and 0: every scan), refine_outer_iterations (each
// round re-associates at the refined pose, so a registration cut short converges) and the jump
// test (max_prior_mahalanobis_squared: a registration that far from the prior falls back).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "dorado/core/lie.hpp"
#include "dorado/mapping/radar_mapper.hpp"
#include "dorado/testing/mapper_input.hpp"
#include "dorado/testing/street_scene.hpp"

namespace dorado::mapping {
namespace {
using testing::PriorInput;

using testing::MakeStreetWorld;
using testing::RadarSimOptions;
using testing::SimulateScan;

constexpr double kDtS = 0.1;
constexpr double kDeg = M_PI / 180.0;

Extrinsics Mount() {
    Extrinsics e;
    e.T_base_radar.translation() = Eigen::Vector3d(1.8, 0.0, 1.2);
    return e;
}

const Eigen::Matrix3Xd &Street() {
    static const Eigen::Matrix3Xd world = MakeStreetWorld(5, 100.0);
    return world;
}

// A scan of the street from T_world_base moving with (v_base, omega_base).
RadarScan ScanFrom(const Eigen::Isometry3d &T_world_base, const Eigen::Vector3d &v_base,
                   const Eigen::Vector3d &omega_base, std::mt19937 &rng) {
    RadarSimOptions sim;
    sim.points_per_scan = 2000;
    sim.ghost_fraction = 0.0;
    return SimulateScan(Street(), T_world_base, Mount().T_base_radar, v_base, omega_base,
                        Eigen::Matrix3Xd(3, 0), Eigen::Vector3d::Zero(), sim, rng, nullptr);
}

// The true pose as the prior, with a few centimetres and tenths of a degree of uncertainty (a
// Doppler prior: no Doppler residuals in the refinement).
MotionPrior PriorAt(const Eigen::Isometry3d &T_world_base) {
    MotionPrior prior;
    prior.T_world_base = T_world_base;
    prior.covariance.setZero();
    prior.covariance.diagonal() << Eigen::Vector3d::Constant(0.05 * 0.05),
        Eigen::Vector3d::Constant(std::pow(0.3 * kDeg, 2));
    prior.kind = PriorKind::kDoppler;
    return prior;
}

// Registers scans from `poses` (moving with the given twist) and returns which updated the map;
// a scan that does not update it must leave the map's size as it was.
std::vector<bool> MapUpdates(const MapperConfig &config,
                             const std::vector<Eigen::Isometry3d> &poses,
                             const Eigen::Vector3d &v_base, const Eigen::Vector3d &omega_base) {
    RadarMapper mapper(config, Mount());
    std::mt19937 rng(3);
    std::vector<bool> updated;
    for (std::size_t k = 0; k < poses.size(); ++k) {
        const std::size_t before = mapper.local_map().size();
        const RegistrationResult r = mapper.Register(ScanFrom(poses[k], v_base, omega_base, rng),
                                                     PriorInput(PriorAt(poses[k]), kDtS));
        EXPECT_FALSE(r.fallback()) << k << ": " << ToString(r.fallback_cause);
        if (r.map_updated) {
            EXPECT_GT(r.map_points_added_world.cols(), 0) << k;
        } else {
            EXPECT_EQ(mapper.local_map().size(), before) << k;
        }
        updated.push_back(r.map_updated);
    }
    return updated;
}

// 10 scans 0.45 m apart along the street: with a 1 m keyframe distance the map is updated at the
// first scan and then every third (1.35 m; two scans are 0.9 m); the angle rule (5 deg) never
// fires on a straight drive. With 0 and 0 every scan updates it.
TEST(MapperOptions, KeyframeDistanceSpacesTheMapUpdates) {
    std::vector<Eigen::Isometry3d> poses;
    for (int k = 0; k < 10; ++k)
        poses.emplace_back(Eigen::Translation3d(10.0 + 0.45 * k, 0.0, 0.0));
    const Eigen::Vector3d v_base(4.5, 0.0, 0.0);
    MapperConfig config;
    config.keyframe_distance_m = 1.0;
    config.keyframe_angle_deg = 5.0;
    const std::vector<bool> expected = {true,  false, false, true,  false,
                                        false, true,  false, false, true};
    EXPECT_EQ(MapUpdates(config, poses, v_base, Eigen::Vector3d::Zero()), expected);
    config.keyframe_distance_m = 0.0;
    config.keyframe_angle_deg = 0.0;
    EXPECT_EQ(MapUpdates(config, poses, v_base, Eigen::Vector3d::Zero()),
              std::vector<bool>(10, true));
}

// 10 scans turning on the spot by 1.5 deg each: the 1 m distance never fires; with a 5 deg
// keyframe angle the map is updated at the first scan and every fourth (6 deg; three are 4.5).
TEST(MapperOptions, KeyframeAngleSpacesTheMapUpdates) {
    std::vector<Eigen::Isometry3d> poses;
    for (int k = 0; k < 10; ++k) {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.translation() = Eigen::Vector3d(20.0, 0.0, 0.0);
        T.linear() = ExpSO3(Eigen::Vector3d(0.0, 0.0, 1.5 * kDeg * k));
        poses.push_back(T);
    }
    const Eigen::Vector3d omega_base(0.0, 0.0, 1.5 * kDeg / kDtS);
    MapperConfig config;
    config.keyframe_distance_m = 1.0;
    config.keyframe_angle_deg = 5.0;
    const std::vector<bool> expected = {true,  false, false, false, true,
                                        false, false, false, true,  false};
    EXPECT_EQ(MapUpdates(config, poses, Eigen::Vector3d::Zero(), omega_base), expected);
}

// A registration cut short (one PCL iteration) from a prior 0.3 m and 1.5 deg off: one round of
// refinement on the correspondences found there keeps much of the prior's rotation error;
// re-associating at the refined pose (refine_outer_iterations rounds) brings the registered pose's
// rotation to what a converged registration gets (measured 0.23 deg with 10 PCL iterations).
TEST(MapperOptions, RefineOuterIterationsReassociateACutShortRegistration) {
    const Eigen::Isometry3d T_first(Eigen::Translation3d(10.0, 0.0, 0.0));
    const Eigen::Isometry3d T_true(Eigen::Translation3d(10.8, 0.0, 0.0));
    const Eigen::Vector3d v_base(8.0, 0.0, 0.0);
    Eigen::Isometry3d T_prior = T_true;
    T_prior.translation() += Eigen::Vector3d(0.1, 0.3, 0.0);
    T_prior.linear() = ExpSO3(Eigen::Vector3d(0.0, 0.0, 1.5 * kDeg));
    MotionPrior prior = PriorAt(T_prior);
    prior.covariance.diagonal() << Eigen::Vector3d::Constant(1.0),
        Eigen::Vector3d::Constant(std::pow(5.0 * kDeg, 2));
    auto rotation_error_deg = [&](int rounds) {
        MapperConfig config;
        config.max_iterations = 1;
        config.refine_outer_iterations = rounds;
        RadarMapper mapper(config, Mount());
        std::mt19937 rng(9);
        mapper.Register(ScanFrom(T_first, v_base, Eigen::Vector3d::Zero(), rng),
                        PriorInput(PriorAt(T_first), kDtS));
        const RegistrationResult r = mapper.Register(
            ScanFrom(T_true, v_base, Eigen::Vector3d::Zero(), rng), PriorInput(prior, kDtS));
        EXPECT_FALSE(r.fallback()) << rounds << ": " << ToString(r.fallback_cause);
        EXPECT_TRUE(r.registered.valid) << rounds;
        return RotationAngle(T_true.linear().transpose() * r.registered.T_world_base.linear()) /
               kDeg;
    };
    const double one = rotation_error_deg(1), eight = rotation_error_deg(8);
    std::printf("registered rotation error: %.3f deg after one round, %.3f deg after eight\n", one,
                eight);
    EXPECT_LT(eight, 0.3);
    EXPECT_GT(one, 2.0 * eight);
}

// The jump test: a prior 0.8 m to the side of the truth with 2 cm of uncertainty (widened by the
// registration's own 0.1 m) puts the registered pose about 8 sigmas away, Mahalanobis^2 ~ 60: above
// max_prior_mahalanobis_squared = 25 the scan falls back to the prior as a jump; with the gate at
// 1000 the same registration is trusted.
TEST(MapperOptions, AJumpBeyondThePriorsGateFallsBackToThePrior) {
    const Eigen::Isometry3d T_first(Eigen::Translation3d(10.0, 0.0, 0.0));
    const Eigen::Isometry3d T_true(Eigen::Translation3d(10.8, 0.0, 0.0));
    const Eigen::Vector3d v_base(8.0, 0.0, 0.0);
    MotionPrior prior = PriorAt(Eigen::Isometry3d(Eigen::Translation3d(10.8, 0.8, 0.0)));
    prior.covariance.diagonal().head<3>().setConstant(0.02 * 0.02);
    auto second_scan = [&](double gate) {
        MapperConfig config;
        config.max_prior_mahalanobis_squared = gate;
        RadarMapper mapper(config, Mount());
        std::mt19937 rng(9);
        mapper.Register(ScanFrom(T_first, v_base, Eigen::Vector3d::Zero(), rng),
                        PriorInput(PriorAt(T_first), kDtS));
        return mapper.Register(ScanFrom(T_true, v_base, Eigen::Vector3d::Zero(), rng),
                               PriorInput(prior, kDtS));
    };
    const RegistrationResult gated = second_scan(25.0);
    std::printf("Mahalanobis^2 of the registration from the prior: %.1f\n",
                gated.prior_mahalanobis_squared);
    EXPECT_EQ(gated.fallback_cause, FallbackCause::kJump) << ToString(gated.fallback_cause);
    // The registration at the truth, 0.8 m from the prior across a variance of 0.02^2 + 0.1^2.
    EXPECT_NEAR(gated.prior_mahalanobis_squared, 0.8 * 0.8 / (0.02 * 0.02 + 0.1 * 0.1), 10.0);
    EXPECT_TRUE(gated.T_world_base.isApprox(prior.T_world_base));
    EXPECT_FALSE(gated.registered.valid);

    const RegistrationResult trusted = second_scan(1000.0);
    ASSERT_FALSE(trusted.fallback()) << ToString(trusted.fallback_cause);
    EXPECT_NEAR(trusted.prior_mahalanobis_squared, gated.prior_mahalanobis_squared, 1e-9);
    EXPECT_TRUE(trusted.registered.valid);
}

// After a fallback the pose is the prior's, not the map's: its uncertainty relative to the map
// grows with every fallback, so a registration that the jump test refused is taken once the
// compounded prior covers it, instead of every later scan being refused against a prior that
// starts from the wrong pose (the lock-out). A prior 1 m to the side with 0.1 m of uncertainty per
// scan, widened by the registration's 0.1 m: Mahalanobis^2 1 / (k 0.1^2 + 0.1^2) after k
// compounded intervals: 50, 33, 25, 20 (trusted).
TEST(MapperOptions, FallbacksWidenThePriorUntilTheMapIsTrustedAgain) {
    const Eigen::Vector3d v_base(2.0, 0.0, 0.0);
    const Eigen::Vector3d offset(0.0, 1.0, 0.0);
    MapperConfig config;
    config.update_map_on_fallback = false;  // the map holds only registered scans
    RadarMapper mapper(config, Mount());
    std::mt19937 rng(9);
    auto T_true = [&](int k) {
        return Eigen::Isometry3d(Eigen::Translation3d(10.0 + 0.2 * k, 0.0, 0.0));
    };
    mapper.Register(ScanFrom(T_true(0), v_base, Eigen::Vector3d::Zero(), rng),
                    PriorInput(PriorAt(T_true(0)), kDtS));
    std::vector<double> mahalanobis2;
    RegistrationResult result;
    for (int k = 1; k <= 10; ++k) {
        // The true motion from the previous pose: on the wrong side once a scan fell back.
        MotionPrior prior = PriorAt(T_true(k));
        prior.T_world_base.translation() += offset;
        prior.covariance.diagonal().head<3>().setConstant(0.1 * 0.1);
        result = mapper.Register(ScanFrom(T_true(k), v_base, Eigen::Vector3d::Zero(), rng),
                                 PriorInput(prior, kDtS));
        mahalanobis2.push_back(result.prior_mahalanobis_squared);
        std::printf("scan %d: %s, Mahalanobis^2 %.1f\n", k, ToString(result.fallback_cause),
                    result.prior_mahalanobis_squared);
        if (!result.fallback()) break;
        EXPECT_EQ(result.fallback_cause, FallbackCause::kJump) << "scan " << k;
    }
    ASSERT_GE(mahalanobis2.size(), 3u);
    EXPECT_NEAR(mahalanobis2[0], 50.0, 10.0);
    EXPECT_NEAR(mahalanobis2[1], 33.3, 7.0);  // 50 again if the fallback's pose counted as exact
    EXPECT_LT(mahalanobis2[1], 0.8 * mahalanobis2[0]);
    ASSERT_FALSE(result.fallback()) << "still refused after 10 scans";
    EXPECT_LE(mahalanobis2.size(), 5u);
    // The registration (the map's chain) back near the truth: within a quarter of the prior's 1 m.
    ASSERT_TRUE(result.registered.valid);
    const int k = static_cast<int>(mahalanobis2.size());
    EXPECT_LT((result.registered.T_world_base.translation() - T_true(k).translation()).norm(),
              0.25);
}

}  // namespace
}  // namespace dorado::mapping
