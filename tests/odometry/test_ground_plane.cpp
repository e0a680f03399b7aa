// The ground-plane attitude: a synthetic tilted road with known roll and pitch, noise and
// outliers (trees above it, multipath mirror images below it) must give that roll and pitch, with
// a covariance that matches the scatter over seeded trials; a scan without ground must be a named
// fallback; the odometry must pull a wrong initial pitch towards the road's.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <limits>
#include <random>

#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/odometry/doppler_odometry.hpp"
#include "dorado/odometry/ground_plane.hpp"
#include "plane_inliers.hpp"

namespace dorado::odometry {
namespace {

constexpr double kDeg = DegToRad(1.0);

// The road 0.25 m below the base origin (the vehicle's base height, which the odometry copies
// from VehicleGeometry).
GroundPlaneConfig Plane() {
    GroundPlaneConfig c;
    c.base_height_m = 0.25;
    return c;
}

struct Road {
    double roll = 3.0 * kDeg, pitch = -5.0 * kDeg;  // the base relative to the road
    double base_height = 0.25;
    double noise_scale = 0.7;  // vertical noise = scale * sqrt(floor^2 + (r sigma_el)^2)
    double outlier_fraction = 0.3;
    int points = 500;
};

/// Points in the base frame: on the plane through (0, 0, -h) with the normal of a base rolled and
/// pitched by (roll, pitch) relative to it, plus outliers well off it.
Eigen::Matrix3Xd MakeRoad(const Road &road, const GroundPlaneConfig &c, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> distance(2.0, 14.0), azimuth(-50.0, 50.0), u(0.0, 1.0);
    std::normal_distribution<double> gauss(0.0, 1.0);
    // R_plane_base = Ry(pitch) Rx(roll): the plane's normal in the base frame is row 3 of it.
    const Eigen::Matrix3d R_plane_base =
        RotationFromRollPitchYaw(Eigen::Vector3d(road.roll, road.pitch, 0.0));
    const Eigen::Vector3d n = R_plane_base.transpose() * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d origin(0.0, 0.0, -road.base_height);
    const double floor2 = 0.25 * c.inlier_threshold_m * c.inlier_threshold_m;
    const double sigma_el = c.elevation_sigma_deg * kDeg;
    Eigen::Matrix3Xd points(3, road.points);
    for (int i = 0; i < road.points; ++i) {
        const double s = distance(rng), az = azimuth(rng) * kDeg;
        const Eigen::Vector2d xy(s * std::cos(az), s * std::sin(az));
        // On the plane: n . (p - origin) = 0.
        const double z = origin.z() - (n.x() * xy.x() + n.y() * xy.y()) / n.z();
        Eigen::Vector3d p(xy.x(), xy.y(), z);
        const double sigma =
            road.noise_scale * std::sqrt(floor2 + p.squaredNorm() * sigma_el * sigma_el);
        p += sigma * gauss(rng) * n;
        if (u(rng) < road.outlier_fraction) p.z() += (u(rng) < 0.5 ? -1.0 : 1.0) * (1.0 + u(rng));
        points.col(i) = p;
    }
    return points;
}

TEST(GroundPlane, TiltedRoadWithOutliersGivesItsRollAndPitch) {
    const GroundPlaneConfig config = Plane();
    const Road road;
    const Eigen::Matrix3Xd points = MakeRoad(road, config, 1);
    const GroundObservation obs =
        FitGroundPlane(config, points, std::vector<bool>(points.cols(), true));
    ASSERT_TRUE(obs.valid) << ToString(obs.fallback);
    EXPECT_NEAR(obs.roll_pitch_rad.x(), road.roll, 0.3 * kDeg);
    EXPECT_NEAR(obs.roll_pitch_rad.y(), road.pitch, 0.3 * kDeg);
    EXPECT_NEAR(obs.height_m, -road.base_height, 0.03);
    // About 70 % of the points are road; the outliers are at least 1 m off it.
    EXPECT_GT(obs.inliers, 300);
    EXPECT_LT(obs.inliers, 380);
}

TEST(GroundPlane, UnevenGroundAndUnknownHeightAreNamedFallbacks) {
    GroundPlaneConfig config = Plane();
    config.max_residual_sigma_m = 0.04;  // flat road: 0.024 m here, the ridged one 0.052 m
    Road road;
    road.outlier_fraction = 0.0;
    road.noise_scale = 0.3;
    Eigen::Matrix3Xd points = MakeRoad(road, config, 5);
    const GroundObservation flat =
        FitGroundPlane(config, points, std::vector<bool>(points.cols(), true));
    ASSERT_TRUE(flat.valid) << ToString(flat.fallback) << " " << flat.residual_sigma_m;
    // Ridges across the road (0.12 m, 4 m wavelength sideways): no one plane fits it.
    for (Eigen::Index i = 0; i < points.cols(); ++i)
        points(2, i) += 0.12 * std::sin(2.0 * M_PI * points(1, i) / 4.0);
    const GroundObservation uneven =
        FitGroundPlane(config, points, std::vector<bool>(points.cols(), true));
    EXPECT_EQ(uneven.fallback, GroundFallback::kUneven)
        << ToString(uneven.fallback) << " " << uneven.residual_sigma_m << " (flat "
        << flat.residual_sigma_m << ")";
    EXPECT_STREQ(ToString(GroundFallback::kUneven), "uneven");
    GroundPlaneConfig unknown = config;
    unknown.base_height_m = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(FitGroundPlane(unknown, points, std::vector<bool>(points.cols(), true)).fallback,
              GroundFallback::kNoBaseHeight);
}

// A level ground seen with 0.5 deg of fit noise.
GroundObservation LevelGround() {
    GroundObservation obs;
    obs.valid = true;
    obs.cov_roll_pitch = Eigen::Matrix2d::Identity() * std::pow(0.5 * kDeg, 2);
    return obs;
}

TEST(GroundPlane, FilterRefusesAnObservationInconsistentWithItsPrediction) {
    GroundAttitudeConfig config;
    config.plane = Plane();
    GroundAttitudeFilter filter(config);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    GroundObservation obs = LevelGround();
    GroundAttitudeStep step = filter.Update(obs, 0.1, T.linear());  // initialises: level
    ASSERT_TRUE(step.updated);
    filter.Predict(Eigen::Matrix3d::Identity() * std::pow(1.0 * kDeg, 2), 0.1);
    // 20 deg of roll after 0.1 s: a kerb under one side, not the vehicle's attitude.
    obs.roll_pitch_rad << 20.0 * kDeg, 0.0;
    step = filter.Update(obs, 0.1, T.linear());
    T.linear() = step.R_world_base;
    EXPECT_FALSE(step.updated);
    EXPECT_EQ(step.observation.fallback, GroundFallback::kInconsistent);
    EXPECT_GT(step.innovation_chi2, config.max_innovation_chi2);
    EXPECT_NEAR(RollPitchYaw(T.linear()).x(), 0.0, 1e-12);
    // 2 deg is within the road's slope: used.
    obs.roll_pitch_rad << 2.0 * kDeg, 0.0;
    step = filter.Update(obs, 0.1, T.linear());
    T.linear() = step.R_world_base;
    EXPECT_TRUE(step.updated);
    EXPECT_GT(RollPitchYaw(T.linear()).x(), 0.0);
}

// A kerb is refused for a few scans; a ground that disagrees for longer than the road's slope is
// correlated is the attitude's own drift beyond the gate: the filter levels with it again instead
// of refusing every later look.
TEST(GroundPlane, FilterLevelsAgainWhenTheGroundDisagreesBeyondTheRoadsCorrelation) {
    GroundAttitudeConfig config;
    config.plane = Plane();
    config.road_correlation_m = 20.0;
    GroundAttitudeFilter filter(config);
    GroundObservation obs = LevelGround();
    GroundAttitudeStep step = filter.Update(obs, 0.5, Eigen::Matrix3d::Identity());  // level
    ASSERT_TRUE(step.updated);
    // The attitude drifted 25 deg in pitch (a biased twist); the ground still says level.
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = RotationFromRollPitchYaw(Eigen::Vector3d(0.0, 25.0 * kDeg, 0.3));
    int refused = 0;
    double travelled_m = 0.0;
    for (; travelled_m < 30.0; travelled_m += 0.5) {
        step = filter.Update(obs, 0.5, T.linear());
        T.linear() = step.R_world_base;
        if (step.relevelled) break;
        EXPECT_EQ(step.observation.fallback, GroundFallback::kInconsistent);
        ++refused;
    }
    ASSERT_TRUE(step.relevelled) << "refused over " << travelled_m << " m";
    EXPECT_TRUE(step.updated);
    EXPECT_EQ(refused, 40);  // 40 x 0.5 m = the road's 20 m correlation, then the 41st levels
    const Eigen::Vector3d rpy = RollPitchYaw(T.linear());
    EXPECT_NEAR(rpy.y(), 0.0, 1e-9);
    EXPECT_NEAR(rpy.z(), 0.3, 1e-9);  // yaw kept
    // Then it filters as usual: a small look is used, not a relevel.
    obs.roll_pitch_rad << 1.0 * kDeg, 0.0;
    step = filter.Update(obs, 0.5, T.linear());
    T.linear() = step.R_world_base;
    EXPECT_TRUE(step.updated);
    EXPECT_FALSE(step.relevelled);
}

TEST(GroundPlane, RollPitchFromSlopeMatchesTheRotationAndItsJacobian) {
    const Eigen::Vector2d slope(0.12, -0.07);
    Eigen::Matrix2d J;
    const Eigen::Vector2d rp = RollPitchFromSlope(slope, &J);
    // The plane z = a x + b y has the normal (-a, -b, 1); R_plane_base^T e_z must be parallel.
    const Eigen::Vector3d n =
        RotationFromRollPitchYaw(Eigen::Vector3d(rp.x(), rp.y(), 0.0)).transpose().col(2);
    EXPECT_LT((n - Eigen::Vector3d(-slope.x(), -slope.y(), 1.0).normalized()).norm(), 1e-12);
    const double h = 1e-7;
    for (int k = 0; k < 2; ++k) {
        const Eigen::Vector2d step = h * Eigen::Vector2d::Unit(k);
        const Eigen::Vector2d numeric =
            (RollPitchFromSlope(slope + step) - RollPitchFromSlope(slope - step)) / (2 * h);
        EXPECT_LT((numeric - J.col(k)).norm(), 1e-6);
    }
}

TEST(GroundPlane, CovarianceMatchesTheScatterOverSeededTrials) {
    const GroundPlaneConfig config = Plane();
    Road road;
    road.points = 300;
    const int trials = 300;
    double nees = 0.0;
    Eigen::Vector2d mean_error = Eigen::Vector2d::Zero();
    for (int t = 0; t < trials; ++t) {
        const Eigen::Matrix3Xd points = MakeRoad(road, config, 100 + t);
        const GroundObservation obs =
            FitGroundPlane(config, points, std::vector<bool>(points.cols(), true));
        ASSERT_TRUE(obs.valid);
        const Eigen::Vector2d e = obs.roll_pitch_rad - Eigen::Vector2d(road.roll, road.pitch);
        nees += e.dot(obs.cov_roll_pitch.inverse() * e);
        mean_error += e;
    }
    nees /= trials;
    mean_error /= trials;
    // Two degrees of freedom: the mean NEES is 2 when the covariance is honest (its standard
    // error over 300 trials is ~0.12); a covariance off by 1.5x in variance fails.
    EXPECT_GT(nees, 1.6);
    EXPECT_LT(nees, 2.5);
    EXPECT_LT(mean_error.norm(), 0.05 * kDeg);  // unbiased
}

TEST(GroundPlane, NoGroundInTheScanIsANamedFallback) {
    const GroundPlaneConfig config = Plane();
    // Walls and trees only: every point 4 m or more above the road.
    Eigen::Matrix3Xd points = MakeRoad(Road{}, config, 3);
    points.row(2).array() += 6.0;
    const GroundObservation obs =
        FitGroundPlane(config, points, std::vector<bool>(points.cols(), true));
    EXPECT_FALSE(obs.valid);
    EXPECT_EQ(obs.fallback, GroundFallback::kFewCandidates);
    EXPECT_STREQ(ToString(obs.fallback), "few_ground_points");

    // A plane 1.5 m above the expected road (a loading ramp, a car roof) is not the ground.
    Eigen::Matrix3Xd ramp = MakeRoad(Road{}, config, 3);
    ramp.row(2).array() += 1.5;
    EXPECT_EQ(FitGroundPlane(config, ramp, std::vector<bool>(ramp.cols(), true)).fallback,
              GroundFallback::kHeightMismatch);

    // The road is there but every point is dynamic (the mask says so): no ground either.
    const Eigen::Matrix3Xd road = MakeRoad(Road{}, config, 4);
    EXPECT_EQ(FitGroundPlane(config, road, std::vector<bool>(road.cols(), false)).fallback,
              GroundFallback::kFewCandidates);

    // A road steeper than max_tilt_deg is not taken for the ground (its near end, where it
    // crosses the window, is a band too short in distance to fix a pitch).
    Road steep;
    steep.pitch = 20.0 * kDeg;
    steep.outlier_fraction = 0.0;  // (mirror images below a steep road can still pose as a
                                   // flatter plane: docs/attitude.md, limits)
    const Eigen::Matrix3Xd hill = MakeRoad(steep, config, 5);
    const GroundObservation steep_obs =
        FitGroundPlane(config, hill, std::vector<bool>(hill.cols(), true));
    EXPECT_FALSE(steep_obs.valid) << "pitch " << steep_obs.roll_pitch_rad.y() / kDeg << " deg, "
                                  << steep_obs.inliers << " of " << steep_obs.candidates;
}

TEST(GroundPlane, ConfigValidationNamesTheKey) {
    GroundAttitudeConfig config;
    config.plane.max_tilt_deg = 90.0;
    try {
        config.Validate();
        FAIL() << "max_tilt_deg = 90 accepted";
    } catch (const std::invalid_argument &e) {
        EXPECT_NE(std::string(e.what()).find("ground.max_tilt_deg"), std::string::npos);
    }
    config = GroundAttitudeConfig{};
    config.road_slope_sigma_deg = 0.0;
    EXPECT_THROW(config.Validate(), std::invalid_argument);
    DopplerOdometryConfig odometry;
    odometry.ground.plane.min_points = 2;
    try {
        odometry.Validate();
        FAIL() << "min_points = 2 accepted";
    } catch (const std::invalid_argument &e) {
        EXPECT_NE(std::string(e.what()).find("ground.min_points"), std::string::npos);
    }
}

/// A radar scan of a level road and of static posts, seen from a base that drives straight at
/// 2 m/s with zero angular rates, its true attitude level.
RadarScan LevelRoadScan(const Extrinsics &extrinsics, int64_t stamp_ns, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> distance(2.0, 14.0), azimuth(-50.0, 50.0),
        height(0.5, 3.0);
    std::normal_distribution<double> gauss(0.0, 1.0);
    const int n = 600;
    RadarScan scan;
    scan.Resize(n);
    scan.stamp_ns = stamp_ns;
    scan.has_power = false;
    const Eigen::Isometry3d T_radar_base = extrinsics.T_base_radar.inverse();
    const Eigen::Vector3d v_radar =
        extrinsics.T_base_radar.linear().transpose() * Eigen::Vector3d(2.0, 0.0, 0.0);
    for (int i = 0; i < n; ++i) {
        const double s = distance(rng), az = azimuth(rng) * kDeg;
        // Half of the points on the road (z_base = -0.25), half on posts above it.
        const double z = i % 2 ? -0.25 + 0.02 * gauss(rng) : height(rng);
        const Eigen::Vector3d p_radar =
            T_radar_base * Eigen::Vector3d(s * std::cos(az), s * std::sin(az), z);
        scan.xyz_radar.col(i) = p_radar;
        scan.doppler_mps[i] = -p_radar.normalized().dot(v_radar) + 0.01 * gauss(rng);
        scan.power_db[i] = 0.0;
    }
    scan.DeriveSphericalFromXyz();
    return scan;
}

TEST(GroundPlane, OdometryPullsAWrongInitialPitchTowardsTheRoad) {
    Extrinsics extrinsics;
    extrinsics.T_base_radar.translation() = Eigen::Vector3d(0.72, 0.0, 0.38);
    const VehicleGeometry geometry{0.256, KinematicModelNoise{}, VehicleModel::kAckermann, 0.25};
    Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
    start.linear() = RotationFromRollPitchYaw(Eigen::Vector3d(0.0, 3.0 * kDeg, 0.0));
    double final_pitch[2] = {0.0, 0.0};
    for (int enabled = 0; enabled < 2; ++enabled) {
        DopplerOdometryConfig config;
        config.ground.enabled = enabled == 1;
        config.ground.road_correlation_m = 2.0;        // a short run: let the road count
        config.ground.initialize_from_ground = false;  // the wrong start is taken as known...
        config.ground.attitude_random_walk_deg_per_sqrt_s = 2.0;  // ...but drifts quickly
        DopplerOdometry odometry(config, extrinsics, geometry);
        odometry.SetInitialPose(start);
        int with_ground = 0;
        for (int k = 0; k < 150; ++k) {  // 10 s at 15 Hz, 20 m
            const OdometryStep step = odometry.Register(
                LevelRoadScan(extrinsics, 1'000'000'000 + k * 66'666'667LL, 10 + k));
            with_ground += step.ground.observation.valid;
        }
        final_pitch[enabled] =
            RollPitchYaw(odometry.trajectory().poses().back().T_world_body.linear()).y();
        if (enabled) {
            EXPECT_GT(with_ground, 140);
        }
    }
    // Without the ground the wrong pitch stays (the rates are zero); with it, the level road
    // pulls it to a small fraction of itself.
    EXPECT_NEAR(final_pitch[0], 3.0 * kDeg, 0.3 * kDeg);
    EXPECT_LT(std::abs(final_pitch[1]), 1.0 * kDeg);
}

TEST(GroundPlane, FirstGroundObservationSetsRollAndPitch) {
    Extrinsics extrinsics;
    extrinsics.T_base_radar.translation() = Eigen::Vector3d(0.72, 0.0, 0.38);
    DopplerOdometryConfig config;
    config.ground.enabled = true;
    DopplerOdometry odometry(
        config, extrinsics,
        VehicleGeometry{0.256, KinematicModelNoise{}, VehicleModel::kAckermann, 0.25});
    Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
    start.linear() = RotationFromRollPitchYaw(Eigen::Vector3d(-2.0 * kDeg, 4.0 * kDeg, 0.5));
    odometry.SetInitialPose(start);
    const OdometryStep step = odometry.Register(LevelRoadScan(extrinsics, 1'000'000'000, 1));
    ASSERT_TRUE(step.ground.updated);
    const Eigen::Vector3d rpy = RollPitchYaw(step.T_world_base.linear());
    EXPECT_LT(rpy.head<2>().norm(), 0.3 * kDeg);  // level with the road
    EXPECT_NEAR(rpy.z(), 0.5, 1e-9);              // yaw kept
}

// The vectorised RANSAC count against a plain loop over the distance as written out, point for
// point: random planes within the tilt gate, 0 to 13 points (padding), many of them placed at the
// inlier threshold where one rounding decides.
TEST(GroundPlane, VectorisedInlierCountEqualsAScalarLoop) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const double threshold = 0.15;
    int on_threshold_counted = 0, on_threshold_refused = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const Eigen::Vector3d theta(-0.3 + 0.2 * u(rng), 0.2 * u(rng), 0.2 * u(rng));
        const double norm = std::sqrt(1.0 + theta.tail<2>().squaredNorm());
        internal::PlanePoints points;
        int expected = 0;
        const int n = trial % 14;
        for (int i = 0; i < n; ++i) {
            const double x = 15.0 * u(rng), y = 15.0 * u(rng);
            const double on_plane = theta.dot(Eigen::Vector3d(1.0, x, y));
            const double z = i % 2 == 0 ? on_plane + 0.3 * u(rng)
                                        : on_plane + (u(rng) < 0.0 ? -1.0 : 1.0) * threshold * norm;
            points.Add(x, y, z);
            const bool inlier =
                std::abs((z - theta.dot(Eigen::Vector3d(1.0, x, y))) / norm) < threshold;
            expected += inlier;
            if (i % 2 == 1) (inlier ? on_threshold_counted : on_threshold_refused)++;
        }
        points.Pad();
        ASSERT_EQ(points.x.size() % internal::PlanePoints::kLanes, 0U);
        ASSERT_EQ(internal::CountPlaneInliers(points, theta, threshold), expected)
            << "trial " << trial;
    }
    // The points at the threshold fall on both sides: the roundings are exercised.
    EXPECT_GT(on_threshold_counted, 100);
    EXPECT_GT(on_threshold_refused, 100);
}

}  // namespace
}  // namespace dorado::odometry
