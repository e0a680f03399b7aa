// What the front end hands the mapper besides the prior, seen through RadarFrontEnd's results on
// synthetic radar of a known drive: the dynamic mask (an overtaking car must stay out of the map)
// and the ground (a start rolled on a level road must get the road's roll and pitch).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "dorado/core/lie.hpp"
#include "dorado/frontend/radar_front_end.hpp"
#include "dorado/testing/street_scene.hpp"

namespace dorado::frontend {
namespace {

using testing::MakeDrive;
using testing::MakeStreetWorld;
using testing::RadarSimOptions;
using testing::SimulateScan;
using testing::TruthSample;

constexpr int64_t kDtNs = 100'000'000;  // 10 Hz
constexpr double kDeg = M_PI / 180.0;

Extrinsics Mount() {
    Extrinsics e;
    e.T_base_radar.translation() = Eigen::Vector3d(1.8, 0.0, 1.2);
    return e;
}

VehicleGeometry Geometry() {
    VehicleGeometry g;
    g.half_wheelbase_m = 1.4;
    return g;
}

// A car-sized block of points (4 x 1.5 x 1 m) starting at `front` (world frame).
Eigen::Matrix3Xd CarPoints(const Eigen::Vector3d &front) {
    std::vector<Eigen::Vector3d> points;
    for (double x = 0.0; x <= 4.0; x += 0.2)
        for (double y = 0.0; y <= 1.5; y += 0.25)
            for (double z = 0.0; z <= 1.0; z += 0.25)
                points.push_back(front + Eigen::Vector3d(x, y, z));
    Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(points.size()));
    for (std::size_t i = 0; i < points.size(); ++i)
        out.col(static_cast<Eigen::Index>(i)) = points[i];
    return out;
}

// The street drive with a car overtaking at 12 m/s in the next lane (y in [-2.5, -1] m, 0.5 to
// 1.5 m above the road), which no static structure of the street occupies. Returns the map's
// points in that lane after `scans` scans.
int MapPointsInTheCarsLane(int scans, const FrontEndConfig &config) {
    const Eigen::Matrix3Xd world = MakeStreetWorld(5);
    const std::vector<TruthSample> truth = MakeDrive(scans, 0.1);
    std::mt19937 rng(21);
    RadarSimOptions sim;
    sim.points_per_scan = 3000;
    RadarFrontEnd front_end(config, Mount(), Geometry());
    const Eigen::Vector3d v_car(12.0, 0.0, 0.0);
    for (int k = 0; k < scans; ++k) {
        const Eigen::Matrix3Xd car =
            CarPoints(Eigen::Vector3d(4.0 + v_car.x() * truth[k].t, -2.5, 0.5));
        RadarScan scan =
            SimulateScan(world, truth[k].T_world_base, Mount().T_base_radar, truth[k].v_base,
                         truth[k].omega_base, car, v_car, sim, rng, nullptr);
        scan.stamp_ns = 1'000'000'000 + k * kDtNs;
        const FrontEndResult r = front_end.Process(scan);
        EXPECT_TRUE(r.accepted) << k;
        EXPECT_FALSE(r.registration.fallback())
            << k << ": " << ToString(r.registration.fallback_cause);
    }
    const Eigen::Matrix3Xd map = front_end.local_map()->Points();
    int in_lane = 0;
    for (Eigen::Index i = 0; i < map.cols(); ++i) {
        const Eigen::Vector3d p = map.col(i);
        in_lane += p.x() > 0.0 && p.x() < 40.0 && p.y() > -2.4 && p.y() < -1.1 && p.z() > 0.6 &&
                   p.z() < 1.4;
    }
    return in_lane;
}

// The front end's Doppler mask reaches the mapper: the car's points, which the ego-velocity
// labels dynamic, never enter the map. Without a mask (use_mask false) they fill the lane.
TEST(FrontEndToMapper, TheDopplerMaskKeepsAnOvertakingCarOutOfTheMap) {
    FrontEndConfig config;
    ASSERT_TRUE(config.use_mask);
    const int masked = MapPointsInTheCarsLane(15, config);
    config.use_mask = false;
    const int unmasked = MapPointsInTheCarsLane(15, config);
    std::printf("map points in the car's lane: %d with the mask, %d without\n", masked, unmasked);
    EXPECT_LE(masked, 2);
    EXPECT_GT(unmasked, 20) << "the car should be in an unmasked map: the test cannot tell";
}

// A level street with a dense road surface; the vehicle drives straight along x at 5 m/s, its base
// rolled by `roll` about its own x axis (a loaded car), 0.5 m above the road, so the road seen
// from the base is tilted by that roll while the true world frame is level with the road.
struct RolledDrive {
    double roll = 3.0 * kDeg;
    double base_height_m = 0.5;
    std::vector<Eigen::Isometry3d> T_world_base;
    std::vector<RadarScan> scans;

    explicit RolledDrive(int count) {
        Eigen::Matrix3Xd street = MakeStreetWorld(3, 80.0);
        std::mt19937 road_rng(4);
        std::uniform_real_distribution<double> x(-5.0, 70.0), y(-8.0, 8.0);
        std::normal_distribution<double> bump(0.0, 0.02);
        Eigen::Matrix3Xd world(3, street.cols() + 12000);
        world.leftCols(street.cols()) = street;
        for (Eigen::Index i = street.cols(); i < world.cols(); ++i)
            world.col(i) << x(road_rng), y(road_rng), bump(road_rng);
        std::mt19937 rng(8);
        RadarSimOptions sim;
        sim.points_per_scan = 3000;
        const Eigen::Vector3d v_base(5.0, 0.0, 0.0);  // along the rolled x axis: the world's x
        for (int k = 0; k < count; ++k) {
            Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
            T.linear() = RotationFromRollPitchYaw(Eigen::Vector3d(roll, 0.0, 0.0));
            T.translation() = Eigen::Vector3d(v_base.x() * 0.1 * k, 0.0, base_height_m);
            RadarScan scan =
                SimulateScan(world, T, Mount().T_base_radar, v_base, Eigen::Vector3d::Zero(),
                             Eigen::Matrix3Xd(3, 0), Eigen::Vector3d::Zero(), sim, rng, nullptr);
            scan.stamp_ns = 1'000'000'000 + k * kDtNs;
            T_world_base.push_back(T);
            scans.push_back(std::move(scan));
        }
    }

    // The front end started at the true position (identity rotation: it does not know the roll)
    // with the ground on or off; returns each scan's roll and pitch error [deg] (the newest pose)
    // and whether the mapper's smoother took the ground.
    struct Run {
        std::vector<Eigen::Vector2d> roll_pitch_error_deg;
        int ground_used = 0;
        int ground_fits = 0;
        int ground_fits_after_first = 0;
    };
    Run Drive(FrontEndConfig config, bool ground) const {
        config.odometry.ground.enabled = ground;
        VehicleGeometry geometry = Geometry();
        geometry.base_height_m = base_height_m;
        RadarFrontEnd front_end(config, Mount(), geometry);
        front_end.Reset(Eigen::Isometry3d(Eigen::Translation3d(T_world_base[0].translation())));
        Run run;
        for (std::size_t k = 0; k < scans.size(); ++k) {
            const FrontEndResult r = front_end.Process(scans[k]);
            EXPECT_TRUE(r.accepted) << k;
            EXPECT_FALSE(r.registration.fallback())
                << k << ": " << ToString(r.registration.fallback_cause);
            run.roll_pitch_error_deg.push_back(
                (RollPitchYaw(r.T_world_base.linear()) - RollPitchYaw(T_world_base[k].linear()))
                    .head<2>() /
                kDeg);
            run.ground_used += r.registration.ground_used;
            run.ground_fits += r.odometry.ground.fit.valid;
            if (k > 0) run.ground_fits_after_first += r.odometry.ground.fit.valid;
        }
        return run;
    }
};

// The ground in the mapper's smoother: the front end hands each scan's road plane (GroundUp) to
// the mapper, whose smoother takes it on every scan with a fit after the first (which starts the
// map at the prior). What the residual does to the pose is test_mapping_ground_factor's and
// test_mapping_pose_smoother's; on this drive its weight (the road's 4 deg of slope) against the
// map's registration moves the roll by hundredths of a degree, so the handover is what is checked.
TEST(FrontEndToMapper, TheGroundReachesTheMappersSmoother) {
    const RolledDrive drive(10);
    FrontEndConfig config;
    const RolledDrive::Run with = drive.Drive(config, true);
    const RolledDrive::Run without = drive.Drive(config, false);
    EXPECT_GE(with.ground_fits_after_first, 8);
    EXPECT_EQ(with.ground_used, with.ground_fits_after_first);
    EXPECT_EQ(without.ground_used, 0);
}

}  // namespace
}  // namespace dorado::frontend
