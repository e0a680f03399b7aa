// The vehicle constraint on the ego-velocity against independent truths: the information-form
// solution of the same linear-Gaussian problem, and an analytic drive whose scans' elevations are
// biased (a real radar's weak axis): without the constraint the car climbs at the rate the bias
// implies, with it the climb stays within the prior.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "dorado/core/angles.hpp"
#include "dorado/odometry/doppler_odometry.hpp"
#include "dorado/odometry/kinematic_model.hpp"
#include "dorado/odometry/vehicle_velocity_prior.hpp"

namespace dorado::odometry {
namespace {

TEST(VehicleVelocityPrior, DisabledLeavesTheVelocityUntouched) {
    const Eigen::Vector3d v(10.0, 0.3, 0.5);
    const Eigen::Matrix3d C = Eigen::Vector3d(0.01, 0.02, 0.3).asDiagonal();
    const ConstrainedVelocity out = ApplyVehicleVelocityPrior(
        VehicleVelocityPrior{}, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), v, C);
    EXPECT_EQ(out.v_radar_mps, v);
    EXPECT_EQ(out.cov_v_radar, C);
}

TEST(VehicleVelocityPrior, EqualsTheInformationFormSolution) {
    // x = argmin (x - v)^T C^-1 (x - v) + (H x + c)^T P^-1 (H x + c), solved in information form.
    Eigen::Matrix3d A;
    A << 0.9, -0.1, 0.2, 0.3, 1.1, -0.4, 0.1, 0.2, 0.8;
    const Eigen::Vector3d c(0.0, 0.2, -0.1), v(12.0, 0.7, 0.9);
    Eigen::Matrix3d L;
    L << 0.1, 0.0, 0.0, 0.02, 0.2, 0.0, -0.03, 0.05, 0.4;
    const Eigen::Matrix3d C = L * L.transpose();
    VehicleVelocityPrior prior;
    prior.enabled = true;
    prior.sigma_lateral_mps = 0.07;
    prior.sigma_vertical_mps = 0.03;
    const ConstrainedVelocity out = ApplyVehicleVelocityPrior(prior, A, c, v, C);
    const Eigen::Matrix<double, 2, 3> H = A.bottomRows<2>();
    const Eigen::Matrix2d P_inv =
        Eigen::Vector2d(1.0 / (0.07 * 0.07), 1.0 / (0.03 * 0.03)).asDiagonal();
    const Eigen::Matrix3d information = C.inverse() + H.transpose() * P_inv * H;
    const Eigen::Vector3d x =
        information.ldlt().solve(C.inverse() * v - H.transpose() * P_inv * c.tail<2>());
    EXPECT_LT((out.v_radar_mps - x).norm(), 1e-9);
    EXPECT_LT((out.cov_v_radar - information.inverse()).norm(), 1e-9);
}

// A 3-D scan of static points seen by a radar moving at v_radar, elevations within +-3 deg (an
// automotive radar's narrow elevation field of view), with the elevation reported `bias_rad` too
// high: the directions are wrong, the Doppler is right.
RadarScan BiasedElevationScan(const Eigen::Vector3d &v_radar, double bias_rad, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> az(-1.0, 1.0), el(-0.05, 0.05), range(5.0, 60.0);
    std::normal_distribution<double> noise(0.0, 0.05);
    const int n = 200;
    RadarScan scan;
    scan.Resize(n);
    scan.has_power = false;
    for (int i = 0; i < n; ++i) {
        const double a = az(rng), e = el(rng), r = range(rng);
        const Eigen::Vector3d d(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
        scan.doppler_mps[i] = -d.dot(v_radar) + noise(rng);
        const double e_seen = e + bias_rad;
        scan.xyz_radar.col(i) =
            r * Eigen::Vector3d(std::cos(e_seen) * std::cos(a), std::cos(e_seen) * std::sin(a),
                                std::sin(e_seen));
        scan.power_db[i] = 0.0;
    }
    scan.DeriveSphericalFromXyz();
    return scan;
}

// 10 s straight at 15 m/s on a flat road (radar 3.5 m ahead of the rear axle, 0.5 m up, looking
// forward), every scan's elevation 2 deg high. Returns the final height of the base.
double FinalHeight(bool constrained) {
    Extrinsics e;
    e.T_base_radar.translation() << 3.5, 0.0, 0.5;
    VehicleGeometry geometry;
    geometry.half_wheelbase_m = 1.35;
    geometry.velocity_prior.enabled = constrained;
    geometry.velocity_prior.sigma_vertical_mps = 0.01;
    DopplerOdometryConfig config;
    config.ego_velocity.sensor.geometry = ScanGeometry::k3d;
    DopplerOdometry odometry(config, e, geometry);
    const Eigen::Vector3d v_radar(15.0, 0.0, 0.0);  // no rotation: the radar moves as the base
    OdometryStep step;
    double v_z_sum = 0.0;
    const int scans = 100;
    for (int k = 0; k <= scans; ++k) {
        RadarScan scan = BiasedElevationScan(v_radar, DegToRad(2.0), 1000 + k);
        scan.stamp_ns = k * 100'000'000LL;
        step = odometry.Register(scan);
        EXPECT_TRUE(step.ego.valid()) << Describe(step.ego);
        v_z_sum += step.ego.v_radar_mps.z();
    }
    // The bias the estimator cannot see: about 15 sin(2 deg) = 0.52 m/s of v_z (less off the
    // boresight, where a shifted elevation is not a rotation of the direction).
    const double v_z_mean = v_z_sum / (scans + 1);
    EXPECT_GT(v_z_mean, 0.3);
    EXPECT_LT(v_z_mean, 0.6);
    return step.T_world_base.translation().z();
}

TEST(VehicleVelocityPrior, BiasedElevationMakesTheUnconstrainedCarClimbButNotTheConstrainedOne) {
    // Unconstrained: eq. (5) turns v_sz into a pitch rate v_sz / (m - s_x) and a base velocity
    // v_sz m / (m - s_x): the car leaves the road by metres within 150 m.
    const double z_free = FinalHeight(false);
    const double z_held = FinalHeight(true);
    EXPECT_GT(std::abs(z_free), 5.0) << z_free;
    // Constrained: the scan's own v_z variance (its covariance says ~0.05 m/s with +-3 deg of
    // elevation; the bias does not show in it) loses to the prior's 0.01 m/s, and v_z ~ 0 implies
    // no pitch rate either. (With 0.05 m/s the climb is only about halved: a soft prior.)
    EXPECT_LT(std::abs(z_held), 0.1 * std::abs(z_free)) << z_held << " vs " << z_free;
}

}  // namespace
}  // namespace dorado::odometry
