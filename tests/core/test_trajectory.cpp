#include <gtest/gtest.h>

#include "dorado/core/imu.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/core/trajectory.hpp"

namespace dorado {
namespace {

Eigen::Isometry3d Yaw(double a, double x) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = ExpSO3(Eigen::Vector3d(0, 0, a));
    T.translation() << x, 0, 0;
    return T;
}

TEST(Trajectory, SortsAndRejectsRepeatedStamps) {
    Trajectory t({{200, Yaw(0, 2)}, {100, Yaw(0, 1)}});
    EXPECT_EQ(t[0].stamp_ns, 100);
    EXPECT_THROW(Trajectory({{100, Yaw(0, 1)}, {100, Yaw(0, 2)}}), std::invalid_argument);
    EXPECT_THROW(t.Append(150, Yaw(0, 0)), std::invalid_argument);
}

TEST(Trajectory, InterpolatesBetweenNeighbours) {
    Trajectory t;
    t.Append(0, Yaw(0.0, 0.0));
    t.Append(1000, Yaw(0.4, 4.0));
    t.Append(3000, Yaw(0.4, 8.0));
    const auto quarter = t.Interpolate(250);
    ASSERT_TRUE(quarter.has_value());
    EXPECT_NEAR(quarter->translation().x(), 1.0, 1e-12);
    EXPECT_NEAR(RotationAngle(quarter->linear()), 0.1, 1e-12);
    const auto later = t.Interpolate(2000);
    ASSERT_TRUE(later.has_value());
    EXPECT_NEAR(later->translation().x(), 6.0, 1e-12);
    EXPECT_FALSE(t.Interpolate(-1).has_value());
    EXPECT_FALSE(t.Interpolate(3001).has_value());
    EXPECT_FALSE(t.Interpolate(2000, 1500).has_value()) << "gap of 2000 ns exceeds 1500";
    EXPECT_TRUE(t.Interpolate(500, 1500).has_value());
    EXPECT_DOUBLE_EQ(t.PathLength(), 8.0);
}

TEST(Imu, MeanAngularVelocityOverAWindow) {
    std::vector<ImuSample> samples;
    for (int i = 0; i < 10; ++i)
        samples.push_back({i * 10, Eigen::Vector3d(i, 0, 1), Eigen::Vector3d::Zero()});
    const Eigen::Vector3d mean = MeanAngularVelocity(samples, 20, 50);  // samples 2..5
    EXPECT_DOUBLE_EQ(mean.x(), 3.5);
    EXPECT_DOUBLE_EQ(mean.z(), 1.0);
    EXPECT_TRUE(MeanAngularVelocity(samples, 1000, 2000).hasNaN());
}

}  // namespace
}  // namespace dorado
