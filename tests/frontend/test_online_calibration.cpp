// On a simulated drive (a weaving path through a yard of trees and posts,
// radar scans with noise and ghosts, the mapper on with the doppler prior), the online calibration
// recovers a deliberately wrong configured s_x (x0.7, x1.3) to within 5 % and keeps a correct one
// within 2 %; the odometry's kinematic model follows the estimate, and the calibration that is
// off leaves the pipeline as it was.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "dorado/core/lie.hpp"
#include "dorado/frontend/radar_front_end.hpp"
#include "dorado/testing/street_scene.hpp"

namespace dorado::frontend {
namespace {

using testing::RadarSimOptions;
using testing::SimulateScan;

constexpr double kTrueSx = 1.2;         // the radar's X position ahead of the rear axle [m]
constexpr int64_t kDtNs = 100'000'000;  // 10 Hz

Extrinsics Mount(double s_x) {
    Extrinsics e;
    e.T_base_radar.translation() = Eigen::Vector3d(s_x, 0.0, 0.8);
    return e;
}

VehicleGeometry Geometry() {
    VehicleGeometry g;
    g.half_wheelbase_m = 0.6;
    return g;
}

// Trees (vertical columns) on a jittered 6 m grid, posts and a flat ground, 200 m x 140 m.
Eigen::Matrix3Xd MakeYard() {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<Eigen::Vector3d> pts;
    for (double x = -30.0; x < 170.0; x += 6.0)
        for (double y = -70.0; y < 70.0; y += 6.0) {
            const double cx = x + 2.0 * u(rng), cy = y + 2.0 * u(rng);
            if (std::abs(cy) < 2.5 && cx > -5.0 && cx < 5.0) continue;  // clear the start
            const double radius = 0.2 + 0.15 * u(rng);
            for (double z = 0.0; z < 3.0 + u(rng); z += 0.4)
                for (int k = 0; k < 4; ++k)
                    pts.emplace_back(cx + radius * std::cos(k * M_PI / 2),
                                     cy + radius * std::sin(k * M_PI / 2), z);
        }
    for (double x = -30.0; x < 170.0; x += 2.0)
        for (double y = -70.0; y < 70.0; y += 2.0) pts.emplace_back(x, y, -0.02 * u(rng));
    Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(pts.size()));
    for (std::size_t i = 0; i < pts.size(); ++i) out.col(static_cast<Eigen::Index>(i)) = pts[i];
    return out;
}

struct Truth {
    Eigen::Isometry3d T_world_base;
    Eigen::Vector3d v_base, omega_base;
};

// A planar weave: 3 m/s, yaw rate 0.35 sin(2 pi t / 12 s); the rear axle has no lateral velocity
// (the kinematic model holds with s_x = kTrueSx).
std::vector<Truth> MakeWeave(int scans) {
    std::vector<Truth> out;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    auto twist_at = [](double s, Eigen::Vector3d &v, Eigen::Vector3d &w) {
        v = Eigen::Vector3d(3.0, 0.0, 0.0);
        w = Eigen::Vector3d(0.0, 0.0, 0.35 * std::sin(2.0 * M_PI * s / 12.0));
    };
    const int substeps = 20;
    for (int k = 0; k < scans; ++k) {
        const double t = k * 0.1;
        Eigen::Vector3d v, w;
        twist_at(t, v, w);
        out.push_back({T, v, w});
        for (int j = 0; j < substeps; ++j) {
            twist_at(t + (j + 0.5) * 0.1 / substeps, v, w);
            Vector6d xi;
            xi << v * 0.1 / substeps, w * 0.1 / substeps;
            T = T * ExpSE3(xi);
        }
    }
    return out;
}

const std::vector<RadarScan> &WeaveScans() {
    static const std::vector<RadarScan> scans = [] {
        const Eigen::Matrix3Xd world = MakeYard();
        const std::vector<Truth> truth = MakeWeave(450);
        std::mt19937 rng(5);
        RadarSimOptions sim;
        sim.points_per_scan = 800;
        sim.max_range_m = 50.0;
        std::vector<RadarScan> out;
        for (std::size_t k = 0; k < truth.size(); ++k) {
            RadarScan scan =
                SimulateScan(world, truth[k].T_world_base, Mount(kTrueSx).T_base_radar,
                             truth[k].v_base, truth[k].omega_base, Eigen::Matrix3Xd(3, 0),
                             Eigen::Vector3d::Zero(), sim, rng, nullptr);
            scan.stamp_ns = 1'000'000'000 + static_cast<int64_t>(k) * kDtNs;
            out.push_back(std::move(scan));
        }
        return out;
    }();
    return scans;
}

struct Outcome {
    double s_x_m = 0.0, sigma_m = 0.0;
    int updates = 0, not_registered = 0;
    double last_omega_error = 0.0;  ///< |odometry yaw rate - truth| on the last scans, mean
};

Outcome RunDrive(double configured_s_x, bool enabled) {
    FrontEndConfig config;
    config.odometry.online_calibration.enabled = enabled;
    RadarFrontEnd front_end(config, Mount(configured_s_x), Geometry());
    const std::vector<Truth> truth = MakeWeave(450);
    Outcome out;
    int tail = 0;
    for (std::size_t k = 0; k < WeaveScans().size(); ++k) {
        const FrontEndResult r = front_end.Process(WeaveScans()[k]);
        const odometry::YawCalibrationStep &c = r.yaw_calibration;
        out.updates += c.status == odometry::YawCalibrationStatus::kUpdated;
        out.not_registered += c.status == odometry::YawCalibrationStatus::kNotRegistered;
        out.s_x_m = c.s_x_m;
        out.sigma_m = c.sigma_s_x_m;
        if (k + 50 >= WeaveScans().size() && r.odometry.ego.valid()) {
            // The interval's mean truth yaw rate (the sine at the interval's midpoint).
            const double t = 0.1 * static_cast<double>(k) - 0.05;
            const double w = 0.35 * std::sin(2.0 * M_PI * t / 12.0);
            out.last_omega_error += std::abs(r.odometry.omega_base_used_radps.z() - w);
            ++tail;
        }
    }
    out.last_omega_error /= std::max(tail, 1);
    return out;
}

TEST(OnlineCalibration, RecoversAWrongConfiguredSxOnASimulatedDrive) {
    for (const double factor : {0.7, 1.3}) {
        const Outcome on = RunDrive(factor * kTrueSx, true);
        std::printf(
            "configured x%.1f: s_x %.4f +- %.4f m (truth %.2f) after %d updates, %d scans "
            "not registered\n",
            factor, on.s_x_m, on.sigma_m, kTrueSx, on.updates, on.not_registered);
        EXPECT_GT(on.updates, 10) << "x" << factor;
        EXPECT_NEAR(on.s_x_m, kTrueSx, 0.05 * kTrueSx) << "configured x" << factor;
        // The odometry's yaw rate followed: far closer to the truth than with the wrong lever.
        const Outcome off = RunDrive(factor * kTrueSx, false);
        std::printf("  mean |yaw rate error| over the last 5 s: %.4f rad/s on, %.4f off\n",
                    on.last_omega_error, off.last_omega_error);
        EXPECT_LT(on.last_omega_error, 0.5 * off.last_omega_error) << "x" << factor;
    }
}

TEST(OnlineCalibration, KeepsACorrectSxWithinTwoPercent) {
    const Outcome on = RunDrive(kTrueSx, true);
    std::printf("configured x1.0: s_x %.4f +- %.4f m after %d updates\n", on.s_x_m, on.sigma_m,
                on.updates);
    EXPECT_GT(on.updates, 10);
    EXPECT_NEAR(on.s_x_m, kTrueSx, 0.02 * kTrueSx);
}

TEST(OnlineCalibration, OffReportsDisabled) {
    FrontEndConfig config;
    config.odometry.online_calibration.enabled = false;
    RadarFrontEnd front_end(config, Mount(0.7 * kTrueSx), Geometry());
    for (int k = 0; k < 30; ++k) {
        const FrontEndResult r = front_end.Process(WeaveScans()[static_cast<std::size_t>(k)]);
        EXPECT_EQ(r.yaw_calibration.status, odometry::YawCalibrationStatus::kDisabled);
    }
}

}  // namespace
}  // namespace dorado::frontend
