// A tunnel along x: its walls, floor and ceiling fix the lateral and vertical position and the
// rotation, but not the position along the tunnel, because every scan sees fresh random points of
// the same surfaces and no point can be matched along x. The static points' Doppler fixes the
// velocity, hence the step along the tunnel: there the mapper's Doppler residuals are what resolve
// the pose. With the default observability gate the same scan is a degenerate-geometry fallback,
// and update_map_on_fallback decides whether it enters the map.
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

using testing::RadarSimOptions;
using testing::SimulateScan;

constexpr double kDtS = 0.1;
constexpr double kSpeedMps = 10.0;  // along the tunnel: the second scan is 1 m ahead

Eigen::Isometry3d RadarMount() {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(1.8, 0.0, 1.2);
    return T;
}

// Random points of the tunnel's walls (y = -5, 5 m), floor (z = 0) and ceiling (z = 6 m) for
// x in [-10, 90] m; each seed draws other points of the same surfaces.
Eigen::Matrix3Xd Tunnel(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> x(-10.0, 90.0), y(-5.0, 5.0), z(0.0, 6.0);
    Eigen::Matrix3Xd points(3, 40000);
    for (Eigen::Index i = 0; i < points.cols(); ++i) {
        const double along = x(rng);
        switch (i % 4) {
            case 0:
                points.col(i) << along, -5.0, z(rng);
                break;
            case 1:
                points.col(i) << along, 5.0, z(rng);
                break;
            case 2:
                points.col(i) << along, y(rng), 0.0;
                break;
            default:
                points.col(i) << along, y(rng), 6.0;
                break;
        }
    }
    return points;
}

// A scan from x_m along the tunnel (level, heading along it) while driving at kSpeedMps.
RadarScan ScanAt(double x_m, unsigned seed, std::mt19937 &rng) {
    RadarSimOptions sim;
    sim.points_per_scan = 3000;
    sim.ghost_fraction = 0.0;
    const Eigen::Isometry3d T_world_base(Eigen::Translation3d(x_m, 0.0, 0.0));
    return SimulateScan(Tunnel(seed), T_world_base, RadarMount(), Eigen::Vector3d(kSpeedMps, 0, 0),
                        Eigen::Vector3d::Zero(), Eigen::Matrix3Xd(3, 0), Eigen::Vector3d::Zero(),
                        sim, rng, nullptr);
}

// The second scan is 1 m ahead; its prior (a constant-velocity one, which carries no Doppler)
// 0.2 m short of it, as after an acceleration, with 0.3 m and 1 deg of uncertainty.
MotionPrior ShortPrior() {
    MotionPrior prior;
    prior.T_world_base = Eigen::Translation3d(0.8, 0.0, 0.0);
    prior.covariance.setZero();
    prior.covariance.diagonal() << Eigen::Vector3d::Constant(0.3 * 0.3),
        Eigen::Vector3d::Constant(std::pow(M_PI / 180.0, 2));
    prior.kind = PriorKind::kConstVel;
    return prior;
}

struct TwoScans {
    RegistrationResult first, second;
    /// Both scans' written poses (the second flushed by Finish), and the map's size after the
    /// first scan (the origin enters at once) and after both are written.
    std::vector<WrittenPose> written;
    std::size_t map_points_after_first = 0, map_points_after_second = 0;
};

TwoScans RegisterTwoScans(const MapperConfig &config) {
    Extrinsics extrinsics;
    extrinsics.T_base_radar = RadarMount();
    RadarMapper mapper(config, extrinsics);
    std::mt19937 rng(5);
    TwoScans out;
    MotionPrior start;  // the first scan starts the map at the true pose
    start.covariance = Matrix6d::Identity() * 1e-6;
    out.first = mapper.Register(ScanAt(0.0, 1, rng), PriorInput(start, kDtS));
    out.map_points_after_first = mapper.local_map().size();
    out.second = mapper.Register(ScanAt(kSpeedMps * kDtS, 2, rng), PriorInput(ShortPrior(), kDtS));
    for (const std::vector<WrittenPose> &written : {out.first.written, out.second.written, mapper.Finish()})
        out.written.insert(out.written.end(), written.begin(), written.end());
    out.map_points_after_second = mapper.local_map().size();
    return out;
}

TEST(Corridor, DopplerResidualsFixTheStepAlongATunnelTheRegistrationCannotSee) {
    MapperConfig config;
    config.min_observability = 0.0;  // let the blind registration through to the refinement
    const TwoScans with = RegisterTwoScans(config);
    ASSERT_TRUE(with.first.first_scan);
    const RegistrationResult &r = with.second;
    ASSERT_FALSE(r.fallback()) << ToString(r.fallback_cause) << " " << r.fallback_detail;
    ASSERT_TRUE(r.registered.valid);
    // The registration does not see along the tunnel: the default gate would refuse it.
    EXPECT_LT(r.observability, MapperConfig{}.min_observability);
    EXPECT_GT(r.doppler_residuals, 100);
    const Eigen::Isometry3d T_true(Eigen::Translation3d(kSpeedMps * kDtS, 0.0, 0.0));
    for (const Eigen::Isometry3d &T : {r.T_world_base, r.registered.T_world_base}) {
        const Eigen::Vector3d error = T.translation() - T_true.translation();
        std::printf("with the Doppler: error %.4f %.4f %.4f m, %.3f deg\n", error.x(), error.y(),
                    error.z(), RotationAngle(T.linear()) * 180.0 / M_PI);
        EXPECT_LT(std::abs(error.x()), 0.02) << "along the tunnel, error " << error.transpose();
        EXPECT_LT(error.tail<2>().norm(), 0.05) << "across it, error " << error.transpose();
        // Sparse noisy points (0.34 deg of angle noise each): measured 0.35 and 0.41 deg.
        EXPECT_LT(RotationAngle(T.linear()), 1.0 * M_PI / 180.0);
    }

    // The same scans without the Doppler residuals: nothing fixes the step along the tunnel, which
    // stays short of the truth where the registration left the prior (measured 0.65 m of 1 m).
    config.use_doppler = false;
    const RegistrationResult blind = RegisterTwoScans(config).second;
    ASSERT_FALSE(blind.fallback()) << ToString(blind.fallback_cause);
    EXPECT_EQ(blind.doppler_residuals, 0);
    for (const Eigen::Isometry3d &T : {blind.T_world_base, blind.registered.T_world_base}) {
        std::printf("without the Doppler: %.4f m along the tunnel (truth 1 m)\n",
                    T.translation().x());
        EXPECT_GT(kSpeedMps * kDtS - T.translation().x(), 0.1) << T.translation().transpose();
    }
}

// update_map_on_fallback: a scan placed at the prior still fills the map (true), or not (false).
// Every scan is a keyframe here, so the setting alone decides.
TEST(Corridor, UpdateMapOnFallbackDecidesWhetherADegenerateScanEntersTheMap) {
    for (const bool update : {true, false}) {
        MapperConfig config;
        config.update_map_on_fallback = update;
        config.keyframe_distance_m = 0.0;
        config.keyframe_angle_deg = 0.0;
        const TwoScans run = RegisterTwoScans(config);
        const RegistrationResult &r = run.second;
        ASSERT_EQ(r.fallback_cause, FallbackCause::kDegenerate) << ToString(r.fallback_cause);
        EXPECT_TRUE(r.T_world_base.isApprox(ShortPrior().T_world_base));
        ASSERT_EQ(run.written.size(), 2u);
        const WrittenPose &second = run.written[1];
        EXPECT_EQ(second.map_updated, update);
        if (update) {
            EXPECT_GT(second.map_points_added_world.cols(), 100);
            EXPECT_GT(run.map_points_after_second, run.map_points_after_first);
        } else {
            EXPECT_EQ(second.map_points_added_world.cols(), 0);
            EXPECT_EQ(run.map_points_after_second, run.map_points_after_first);
        }
    }
}

}  // namespace
}  // namespace dorado::mapping
