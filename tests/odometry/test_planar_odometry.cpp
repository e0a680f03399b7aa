// The planar (2D radar) chain against independent truths: a synthetic 2D scan with a known radar
// velocity and known moving points; a rigid-body twist through the mount (eq. 3 in the plane);
// a constant-twist drive integrated to its exact SE(2) pose with z, roll and pitch held.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "dorado/core/lie.hpp"
#include "dorado/odometry/doppler_odometry.hpp"
#include "dorado/odometry/planar_ego_velocity.hpp"
#include "dorado/odometry/planar_kinematic_model.hpp"

namespace dorado::odometry {
namespace {

// 2D scan (z = 0): `statics` points with Doppler = -d . v + noise, then `movers` points whose
// Doppler is off by 2-8 m/s (either sign).
RadarScan PlanarScan(const Eigen::Vector2d &v_radar, int statics, int movers, double sigma,
                     uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> az(-1.3, 1.3), range(2.0, 80.0), off(2.0, 8.0);
    std::normal_distribution<double> noise(0.0, sigma);
    const int n = statics + movers;
    RadarScan scan;
    scan.Resize(n);
    scan.has_power = false;
    for (int i = 0; i < n; ++i) {
        const double a = az(rng), r = range(rng);
        const Eigen::Vector2d d(std::cos(a), std::sin(a));
        scan.xyz_radar.col(i) << r * d, 0.0;
        scan.doppler_mps[i] = -d.dot(v_radar) + (sigma > 0.0 ? noise(rng) : 0.0);
        if (i >= statics) scan.doppler_mps[i] += (i % 2 ? 1.0 : -1.0) * off(rng);
        scan.power_db[i] = 0.0;
    }
    scan.DeriveSphericalFromXyz();
    return scan;
}

TEST(PlanarEgoVelocity, RecoversTheVelocityAndLabelsTheMovers) {
    const Eigen::Vector2d v(12.0, -3.0);
    PlanarEgoVelocityEstimator estimator{EgoVelocityConfig{}};
    const RadarScan scan = PlanarScan(v, 150, 50, 0.05, 7);
    ASSERT_TRUE(IsPlanarScan(scan));
    const EgoVelocityResult r = estimator.Estimate(scan);
    ASSERT_TRUE(r.valid()) << Describe(r);
    EXPECT_NEAR(r.v_radar_mps.x(), v.x(), 0.05);
    EXPECT_NEAR(r.v_radar_mps.y(), v.y(), 0.05);
    EXPECT_EQ(r.v_radar_mps.z(), 0.0);
    EXPECT_EQ(r.cov_v_radar(2, 2), 0.0);
    for (int i = 150; i < 200; ++i) EXPECT_EQ(r.labels[i], PointLabel::kDynamic) << i;
    int statics = 0;
    for (int i = 0; i < 150; ++i) statics += r.labels[i] == PointLabel::kStatic;
    EXPECT_GE(statics, 140);  // a 3-sigma gate keeps 99.7 %
}

TEST(PlanarEgoVelocity, CovarianceMatchesTheScatterOverScans) {
    // NEES of the 2x2 covariance over 300 noisy scans: mean 2 (chi-square, 2 dof).
    const Eigen::Vector2d v(8.0, 1.5);
    PlanarEgoVelocityEstimator estimator{EgoVelocityConfig{}};
    double nees = 0.0;
    const int scans = 300;
    for (int k = 0; k < scans; ++k) {
        const EgoVelocityResult r = estimator.Estimate(PlanarScan(v, 120, 30, 0.05, 100 + k));
        ASSERT_TRUE(r.valid()) << Describe(r);
        const Eigen::Vector2d e = r.v_radar_mps.head<2>() - v;
        nees += e.dot(r.cov_v_radar.topLeftCorner<2, 2>().inverse() * e);
    }
    EXPECT_NEAR(nees / scans, 2.0, 0.4);
}

TEST(PlanarEgoVelocity, ParallelDirectionsAreDegenerate) {
    RadarScan scan = PlanarScan(Eigen::Vector2d(5.0, 0.0), 30, 0, 0.0, 3);
    for (Eigen::Index i = 0; i < scan.size(); ++i) {  // every point straight ahead
        scan.xyz_radar.col(i) << 5.0 + i, 0.0, 0.0;
        scan.doppler_mps[i] = -5.0;
    }
    const EgoVelocityResult r = PlanarEgoVelocityEstimator{EgoVelocityConfig{}}.Estimate(scan);
    EXPECT_FALSE(r.valid());
    EXPECT_EQ(r.failure, EgoVelocityFailure::kDegenerateGeometry) << Describe(r);
}

// The RadarScenes front-left mount: x 3.86 m, y 0.70 m, yaw 24.98 deg.
Extrinsics CornerMount() {
    Extrinsics e;
    e.T_base_radar.translation() << 3.86, 0.70, 0.0;
    e.T_base_radar.linear() = Eigen::AngleAxisd(0.436, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return e;
}

TEST(PlanarKinematicModel, InvertsARigidBodyTwist) {
    // The car drives 15 m/s forward turning at 0.2 rad/s (no lateral velocity at the rear axle):
    // the radar moves with v_s = v_b + omega e_z x s (eq. 3), seen in its own frame.
    const Extrinsics e = CornerMount();
    const Eigen::Vector3d v_b(15.0, 0.0, 0.0), omega(0.0, 0.0, 0.2);
    const Eigen::Vector3d v_s = v_b + omega.cross(e.T_base_radar.translation());
    const Eigen::Vector3d v_radar = e.T_base_radar.linear().transpose() * v_s;
    const PlanarKinematicModel model(e, VehicleGeometry{});
    const VehicleMotion m = model.Motion(v_radar, Eigen::Matrix3d::Identity() * 1e-4);
    EXPECT_NEAR(m.v_base_mps.x(), 15.0, 1e-9);
    EXPECT_NEAR(m.v_base_mps.y(), 0.0, 1e-12);
    EXPECT_NEAR(m.omega_base_radps.z(), 0.2, 1e-9);
    EXPECT_EQ(m.omega_base_radps.head<2>().norm(), 0.0);
    // The yaw rate's variance: omega = v_sy / s_x, v_s isotropic 1e-4 -> 1e-4 / s_x^2.
    EXPECT_NEAR(m.cov_omega_base(2, 2), 1e-4 / (3.86 * 3.86), 1e-12);
    EXPECT_NEAR((model.BaseVelocity(v_radar, 0.2) - v_b).norm(), 0.0, 1e-9);
    Extrinsics on_axle = e;
    on_axle.T_base_radar.translation().x() = 0.0;
    EXPECT_THROW(PlanarKinematicModel(on_axle, VehicleGeometry{}), std::invalid_argument);
}

TEST(PlanarOdometry, AutoModeDetectsA2DRadarOnceAndIntegratesTheCircle) {
    const Extrinsics e = CornerMount();
    const Eigen::Vector3d v_b(10.0, 0.0, 0.0), omega(0.0, 0.0, 0.15);
    const Eigen::Vector3d v_s = v_b + omega.cross(e.T_base_radar.translation());
    const Eigen::Vector2d v_radar = (e.T_base_radar.linear().transpose() * v_s).head<2>();
    DopplerOdometryConfig config;  // ego_velocity.sensor.geometry = kAuto
    VehicleGeometry geometry;
    geometry.half_wheelbase_m = 1.4;
    geometry.model_noise = KinematicModelNoise{};
    DopplerOdometry odometry(config, e, geometry);
    Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
    start.translation() << 1.0, 2.0, 0.3;  // held: z, roll and pitch of the start
    odometry.SetInitialPose(start);
    int detected = 0;
    OdometryStep step;
    const int scans = 50;
    for (int k = 0; k <= scans; ++k) {
        RadarScan scan = PlanarScan(v_radar, 100, 0, 0.0, k);
        scan.stamp_ns = k * 100'000'000LL;
        step = odometry.Register(scan);
        ASSERT_TRUE(step.ego.valid()) << Describe(step.ego);
        EXPECT_TRUE(step.planar);
        detected += step.planar_detected;
    }
    EXPECT_EQ(detected, 1);
    Vector6d xi;
    xi << v_b, omega;
    const Eigen::Isometry3d truth = start * ExpSE3(xi * (scans * 0.1));
    EXPECT_NEAR((step.T_world_base.translation() - truth.translation()).norm(), 0.0, 1e-6);
    EXPECT_NEAR(step.T_world_base.translation().z(), 0.3, 1e-12);
    EXPECT_NEAR(RotationAngle(step.T_world_base.linear().transpose() * truth.linear()), 0.0, 1e-9);
}

}  // namespace
}  // namespace dorado::odometry
