// The window smoother on a noisy constant-twist scene: Doppler of static points at every
// scan, the kinematic model, no map. With a nearly rigid WNOA prior the window averages the scans'
// Doppler, so the newest twist's error falls as 1 / sqrt(number of scans in the window) =
// 1 / sqrt(K + 1) (K free states plus the anchor, whose twist is estimated too).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "dorado/core/lie.hpp"
#include "dorado/mapping/radar_mapper.hpp"
#include "dorado/mapping/window_smoother.hpp"

namespace dorado::mapping {
namespace {

struct Scene {
    Extrinsics extrinsics;
    VehicleGeometry geometry;
    Eigen::Vector3d v_base, omega_base;  // obey eq. 5: v_y = 0, v_z = m w_y, w_x = 0
    Scene() {
        extrinsics.T_base_radar = ExpSE3((Vector6d() << 3.5, 0.2, 0.9, 0.0, 0.02, 0.1).finished());
        geometry.half_wheelbase_m = 1.4;
        geometry.model_noise.sigma_lateral_mps = 1e-3;
        geometry.model_noise.sigma_vertical_mps = 1e-3;
        geometry.model_noise.sigma_roll_rate_radps = 1e-3;
        geometry.model_noise.sigma_icr_x_m = 0.0;
        geometry.model_noise.rear_slip_rad_per_mps2 = 0.0;
        omega_base = Eigen::Vector3d(0.0, 0.01, 0.2);
        v_base = Eigen::Vector3d(6.0, 0.0, geometry.half_wheelbase_m * omega_base.y());
    }
};

// One scan's Doppler: 100 static points in random directions, noise sigma.
WindowScan NoisyScan(const Scene &scene, std::mt19937 &rng, double sigma, double dt) {
    const Eigen::Isometry3d &T = scene.extrinsics.T_base_radar;
    const Eigen::Vector3d v_radar =
        T.linear().transpose() * (scene.v_base + scene.omega_base.cross(T.translation()));
    std::normal_distribution<double> n(0.0, 1.0);
    WindowScan scan;
    scan.dt_s = dt;
    for (int k = 0; k < 100; ++k) {
        const Eigen::Vector3d d = Eigen::Vector3d(n(rng), n(rng), 0.3 * n(rng)).normalized();
        scan.doppler.push_back({d, -d.dot(v_radar) + sigma * n(rng)});
    }
    scan.v_base_initial = scene.v_base + Eigen::Vector3d(0.2, 0.1, -0.1);
    scan.omega_base_initial = scene.omega_base;
    return scan;
}

// RMS error of the newest state's v_base over trials, with K free states (K + 1 scans).
double NewestTwistRms(int K, int trials) {
    const Scene scene;
    WindowConfig config;
    config.size = K;
    config.qc_linear = Eigen::Vector3d::Constant(1e-8);  // a constant twist: average everything
    config.qc_angular = Eigen::Vector3d::Constant(1e-8);
    config.max_iterations = 20;
    WindowNoise noise{0.1, RobustKernel::kNone, 1.0};
    std::mt19937 rng(42 + K);
    const double dt = 0.1;
    double sum_sq = 0.0;
    for (int t = 0; t < trials; ++t) {
        WindowSmoother smoother(config, noise, scene.extrinsics, scene.geometry);
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        WindowState newest;
        for (int k = 0; k <= K; ++k) {
            WindowScan scan = NoisyScan(scene, rng, 0.1, dt);
            scan.T_world_base_initial = T;  // true poses as the starting point
            newest = smoother.Add(scan);
            T = T * ExpSE3((Vector6d() << scene.v_base * dt, scene.omega_base * dt).finished());
        }
        sum_sq += (newest.v_base_mps - scene.v_base).squaredNorm();
    }
    return std::sqrt(sum_sq / trials);
}

TEST(WindowSmoother, TwistErrorFallsAsOneOverSqrtOfTheWindow) {
    const double e1 = NewestTwistRms(1, 150);   // 2 scans
    const double e3 = NewestTwistRms(3, 80);    // 4 scans
    const double e15 = NewestTwistRms(15, 40);  // 16 scans
    // 1 / sqrt(n): ratios sqrt(2) and sqrt(8) between 2, 4 and 16 scans; +-20 % for sampling.
    std::printf("rms %g %g %g\n", e1, e3, e15);
    EXPECT_NEAR(e1 / e3, std::sqrt(2.0), 0.2 * std::sqrt(2.0)) << e1 << " " << e3;
    EXPECT_NEAR(e1 / e15, std::sqrt(8.0), 0.2 * std::sqrt(8.0)) << e1 << " " << e15;
    // And the single-scan level is the Doppler least-squares level (~ sigma sqrt(3 / 100) / ...).
    EXPECT_LT(e15, 0.01);
}

TEST(WindowSmoother, RefinementSpellings) {
    EXPECT_STREQ(ToString(Refinement::kWindow), "window");
    EXPECT_EQ(ParseRefinement("window"), Refinement::kWindow);
    EXPECT_THROW((void)ParseRefinement("windo"), std::invalid_argument);
    WindowConfig bad;
    bad.size = 0;
    EXPECT_THROW(bad.Validate(), std::invalid_argument);
}

}  // namespace
}  // namespace dorado::mapping
