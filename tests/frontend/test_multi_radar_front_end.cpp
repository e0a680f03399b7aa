// Several radars into one map against an independent truth (dorado/testing/planar_rig.hpp): the
// vehicle's pose at the reference radar's stamps, with the radars firing at their own times and
// one mount half a degree off its published yaw.
#include <gtest/gtest.h>

#include <cmath>

#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/frontend/multi_radar_front_end.hpp"
#include "dorado/testing/planar_rig.hpp"

namespace dorado::frontend {
namespace {

struct MapRun {
    double end_error_m = 0.0, end_heading_error_deg = 0.0, path_m = 0.0;
    int sweeps = 0, fallbacks = 0, first_radars = 0;
    double mount_offset_deg = 0.0;
};

MapRun Map(const testing::PlanarRig &rig, bool calibrate, double seconds = 24.0) {
    FrontEndConfig config;
    config.odometry.ego_velocity.sensor.geometry = ScanGeometry::kPlanar;
    VehicleGeometry vehicle;
    vehicle.velocity_prior.enabled = true;
    vehicle.velocity_prior.sigma_lateral_mps = 0.1;
    odometry::PlanarTwistFilterConfig filter;
    filter.calibrate_mount_yaw = calibrate;
    MultiRadarFrontEnd front_end(config, rig.published, Eigen::Isometry3d::Identity(), vehicle,
                                 filter);
    MapRun run;
    uint64_t seed = 1;
    const int cycles = static_cast<int>(seconds * 10.0);
    for (int i = 0; i < cycles; ++i) {
        // The other radars fire before the reference in each 0.1 s cycle, at their own offsets.
        for (std::size_t k : {std::size_t{1}, std::size_t{2}, std::size_t{3}, std::size_t{0}}) {
            const double t = 0.1 * i + (k == 0 ? 0.09 : 0.021 * static_cast<double>(k));
            const RadarScanStep step = front_end.Process(k, rig.Scan(k, t, seed++));
            EXPECT_TRUE(step.accepted) << step.skip_reason;
            if (!step.sweep) continue;
            ++run.sweeps;
            run.fallbacks += step.sweep->registration.fallback() && !step.sweep->prior_first_scan;
            if (run.sweeps == 1) run.first_radars = step.sweep_radars;
        }
    }
    // The written poses: one per sweep once Finish flushes the smoother.
    front_end.Finish();
    const Trajectory &trajectory = front_end.trajectory();
    EXPECT_EQ(trajectory.size(), static_cast<std::size_t>(run.sweeps));
    const double t0 = 0.09, t1 = 0.1 * (cycles - 1) + 0.09;
    // The map's world is the first sweep's base frame: compare motions from there.
    const Eigen::Isometry3d truth = rig.Pose(t0).inverse() * rig.Pose(t1);
    const Eigen::Isometry3d estimate = trajectory.poses().back().T_world_body;
    run.end_error_m = (estimate.translation() - truth.translation()).norm();
    run.end_heading_error_deg =
        RadToDeg(std::abs(LogSO3(estimate.linear().transpose() * truth.linear()).z()));
    run.path_m = rig.speed_mps * (t1 - t0);
    run.mount_offset_deg = RadToDeg(front_end.twist_filter().mount_yaw_offset_rad(1));
    return run;
}

TEST(MultiRadarFrontEnd, MapsEveryRadarEachAtItsOwnTime) {
    const testing::PlanarRig rig;
    const MapRun run = Map(rig, true);
    EXPECT_EQ(run.sweeps, 240);
    EXPECT_EQ(run.first_radars, 4);  // every radar's scan joined the first sweep
    EXPECT_EQ(run.fallbacks, 0);
    EXPECT_LT(run.end_error_m, 0.005 * run.path_m) << run.end_error_m << " m of " << run.path_m;
    EXPECT_LT(run.end_heading_error_deg, 0.5);
}

TEST(MultiRadarFrontEnd, AMountOffItsPublishedYawIsCalibratedAndTheMapStaysTrue) {
    testing::PlanarRig rig;
    rig.yaw_offset_deg = {0.0, 1.0, 0.0, 0.0};
    const MapRun calibrated = Map(rig, true);
    const MapRun fixed = Map(rig, false);
    EXPECT_NEAR(calibrated.mount_offset_deg, 1.0, 0.1);
    EXPECT_EQ(fixed.mount_offset_deg, 0.0);
    // Both maps stay within 0.5 % of the path: the registration absorbs one radar's degree.
    EXPECT_LT(calibrated.end_error_m, 0.005 * calibrated.path_m) << calibrated.end_error_m;
    EXPECT_LT(fixed.end_error_m, 0.005 * fixed.path_m) << fixed.end_error_m;
}

TEST(MultiRadarFrontEnd, ScansOlderThanTheLastSweepAreNotUsed) {
    const testing::PlanarRig rig;
    FrontEndConfig config;
    config.odometry.ego_velocity.sensor.geometry = ScanGeometry::kPlanar;
    MultiRadarFrontEnd front_end(config, rig.published, Eigen::Isometry3d::Identity(), {});
    EXPECT_TRUE(front_end.Process(0, rig.Scan(0, 1.0, 1)).sweep.has_value());
    const RadarScanStep late = front_end.Process(2, rig.Scan(2, 0.95, 2));
    EXPECT_FALSE(late.accepted);
    EXPECT_NE(late.skip_reason.find("not after the last sweep"), std::string::npos);
    EXPECT_THROW((void)front_end.Process(4, rig.Scan(0, 1.1, 3)), std::out_of_range);
    config.odometry.ego_velocity.sensor.geometry = ScanGeometry::k3d;
    EXPECT_THROW(MultiRadarFrontEnd(config, rig.published, Eigen::Isometry3d::Identity(), {}),
                 std::invalid_argument);
}

}  // namespace
}  // namespace dorado::frontend
