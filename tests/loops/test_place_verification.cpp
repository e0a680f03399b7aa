// Place recognition and verification on the synthetic street: the same place seen from two
// anchors is found and registered to its known relative pose; different places are not.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dorado/loops/loop_verification.hpp"
#include "dorado/loops/place_recognition.hpp"
#include "synthetic_drive.hpp"

namespace dorado::loops {
namespace {

Eigen::Isometry3d Planar(double x, double y, double yaw) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() << x, y, 0.0;
    return T;
}

// What a drive of 40 m along x from `start` saw, in the frame of `T_world_anchor`.
Eigen::Matrix3Xf SubmapPoints(const test::StreetWorld &world, double start_x,
                              const Eigen::Isometry3d &T_world_anchor, unsigned seed) {
    std::mt19937 random(seed);
    std::vector<Eigen::Vector3f> points;
    for (double x = start_x; x < start_x + 40.0; x += 1.0) {
        const Eigen::Matrix3Xd seen = world.Seen(Planar(x, 0.0, 0.0), random);
        const Eigen::Isometry3d T_anchor_base = T_world_anchor.inverse() * Planar(x, 0.0, 0.0);
        for (Eigen::Index i = 0; i < seen.cols(); ++i)
            points.push_back((T_anchor_base * seen.col(i)).cast<float>());
    }
    Eigen::Matrix3Xf out(3, static_cast<Eigen::Index>(points.size()));
    for (std::size_t i = 0; i < points.size(); ++i)
        out.col(static_cast<Eigen::Index>(i)) = points[i];
    return out;
}

class PlaceTest : public ::testing::Test {
  protected:
    test::StreetWorld world = test::StreetWorld::Make(11, -60.0, 400.0, -60.0, 60.0, {}, {0.0});
    // The first visit anchored at x = 0; the second, 3 m further and seen from an anchor that the
    // drifted odometry put 2 m aside and turned 20 deg: T_first_second is known.
    Eigen::Isometry3d T_world_first = Planar(0.0, 0.0, 0.0);
    Eigen::Isometry3d T_world_second = Planar(3.0, 2.0, 20.0 * M_PI / 180.0);
    Eigen::Matrix3Xf first = SubmapPoints(world, 0.0, T_world_first, 1);
    Eigen::Matrix3Xf second = SubmapPoints(world, 3.0, T_world_second, 2);
    Eigen::Matrix3Xf elsewhere = SubmapPoints(world, 250.0, T_world_first, 3);
    Eigen::Isometry3d T_first_second = T_world_first.inverse() * T_world_second;
};

TEST_F(PlaceTest, SamePlaceMatchesWithItsRelativePose) {
    const PlaceConfig config;
    const PlaceMatch match =
        MatchPlaces(DescribePlace(second, config), DescribePlace(first, config), config);
    ASSERT_TRUE(match.found) << match.matches << " matches, " << match.inliers << " inliers";
    EXPECT_NEAR(match.xy_yaw_candidate_query.x(), T_first_second.translation().x(), 1.0);
    EXPECT_NEAR(match.xy_yaw_candidate_query.y(), T_first_second.translation().y(), 1.0);
    EXPECT_NEAR(match.xy_yaw_candidate_query.z(), 20.0 * M_PI / 180.0, 2.0 * M_PI / 180.0);
}

TEST_F(PlaceTest, DifferentPlacesDoNotMatch) {
    const PlaceConfig config;
    const PlaceMatch match =
        MatchPlaces(DescribePlace(elsewhere, config), DescribePlace(first, config), config);
    EXPECT_FALSE(match.found) << match.inliers << " inliers";
}

TEST_F(PlaceTest, VerificationRecoversTheRelativePose) {
    const VerificationConfig config;
    // A guess 1.5 m and 4 deg off, as a place match gives.
    const Eigen::Isometry3d guess = T_first_second * Planar(1.0, -1.1, 4.0 * M_PI / 180.0);
    const Verification v = VerifyLoop(first, second, guess, config);
    ASSERT_TRUE(v.accepted()) << ToString(v.failure) << " overlap " << v.overlap << " rms "
                              << v.rms_m << " observability " << v.observability;
    const Vector6d error = LogSE3(T_first_second.inverse() * v.T_candidate_query);
    EXPECT_LT(error.head<2>().norm(), 0.1);
    EXPECT_LT(std::abs(error(5)), 0.3 * M_PI / 180.0);
    // Its covariance is honest about the error it made (a loose 5-sigma check per axis).
    const Matrix6d covariance = v.information.inverse();
    for (int axis : {0, 1, 5})
        EXPECT_LT(std::abs(error(axis)), 5.0 * std::sqrt(covariance(axis, axis)) + 0.02);
}

TEST_F(PlaceTest, VerificationRejectsDifferentPlaces) {
    const Verification v =
        VerifyLoop(first, elsewhere, Eigen::Isometry3d::Identity(), VerificationConfig{});
    EXPECT_FALSE(v.accepted());
}

TEST(PlaceDegeneracy, CorridorOfTwoWallsIsDegenerate) {
    // Two long parallel walls: nothing fixes the position along them.
    std::vector<Eigen::Vector3f> points;
    for (double x = -40.0; x <= 40.0; x += 0.5)
        for (double z = 0.0; z <= 2.0; z += 0.5) {
            points.emplace_back(x, -6.0, z);
            points.emplace_back(x, 6.0, z);
        }
    Eigen::Matrix3Xf walls(3, static_cast<Eigen::Index>(points.size()));
    for (std::size_t i = 0; i < points.size(); ++i)
        walls.col(static_cast<Eigen::Index>(i)) = points[i];
    const Verification v = VerifyLoop(walls, walls, Planar(0.3, 0.2, 0.0), VerificationConfig{});
    EXPECT_EQ(v.failure, VerificationFailure::kDegenerate)
        << ToString(v.failure) << " observability " << v.observability;
}

}  // namespace
}  // namespace dorado::loops
