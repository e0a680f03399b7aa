// The road's up-vector that the front end hands the mapper (GroundUpFromFit) from the plane fit of
// a synthetic road seen at a known roll and pitch: the vector must be the world's Z axis in the
// base frame written out by hand, (-sin p, sin r cos p, cos r cos p), and its covariance the
// fit's (roll on y, pitch on x) plus the road's slope.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/frontend/radar_front_end.hpp"
#include "dorado/odometry/ground_plane.hpp"

namespace dorado::frontend {
namespace {

constexpr double kDeg = DegToRad(1.0);

TEST(GroundUpFromFit, IsTheWorldsUpInTheBaseFrameOfARoadOfKnownRollAndPitch) {
    const double roll = 3.0 * kDeg, pitch = -2.0 * kDeg, height = 0.3;
    // Points on the road through (0, 0, -height) whose normal is the up-vector above, with noise.
    const Eigen::Vector3d n(-std::sin(pitch), std::sin(roll) * std::cos(pitch),
                            std::cos(roll) * std::cos(pitch));
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> distance(2.0, 14.0), azimuth(-20.0, 20.0);
    std::normal_distribution<double> gauss(0.0, 0.02);
    Eigen::Matrix3Xd points(3, 400);
    for (int i = 0; i < points.cols(); ++i) {
        const double s = distance(rng), az = azimuth(rng) * kDeg;
        const Eigen::Vector2d xy(s * std::cos(az), s * std::sin(az));
        const double z = -height - (n.x() * xy.x() + n.y() * xy.y()) / n.z();
        points.col(i) = Eigen::Vector3d(xy.x(), xy.y(), z) + gauss(rng) * n;
    }
    odometry::GroundAttitudeConfig ground;
    ground.plane.base_height_m = height;
    const odometry::GroundObservation fit =
        odometry::FitGroundPlane(ground.plane, points, std::vector<bool>(points.cols(), true));
    ASSERT_TRUE(fit.valid) << odometry::ToString(fit.fallback);
    const mapping::GroundUp up = GroundUpFromFit(fit, ground);
    EXPECT_LT(std::acos(std::min(1.0, up.up_base.dot(n))), 0.2 * kDeg)
        << up.up_base.transpose() << " vs " << n.transpose();
    EXPECT_NEAR(up.up_base.norm(), 1.0, 1e-12);
    // A narrow fan (+-20 deg) sees the pitch better than the roll: the covariance is anisotropic,
    // and up.x (pitch) must carry the fit's pitch variance, up.y (roll) its roll variance.
    const double slope2 = std::pow(ground.road_slope_sigma_deg * kDeg, 2);
    ASSERT_GT(fit.cov_roll_pitch(0, 0), 2.0 * fit.cov_roll_pitch(1, 1));
    EXPECT_NEAR(up.covariance(0, 0), fit.cov_roll_pitch(1, 1) + slope2, 1e-12);
    EXPECT_NEAR(up.covariance(1, 1), fit.cov_roll_pitch(0, 0) + slope2, 1e-12);
    EXPECT_EQ(up.max_innovation_chi2, ground.max_innovation_chi2);
}

}  // namespace
}  // namespace dorado::frontend
