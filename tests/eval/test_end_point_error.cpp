// End-point error against hand-computed cases: a path driven 2 % too long, a start heading
// error, an estimate expressed in another world frame (which the start alignment removes).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <stdexcept>

#include "dorado/core/angles.hpp"
#include "dorado/eval/end_point_error.hpp"

namespace dorado::eval {
namespace {

Eigen::Isometry3d Pose(double x, double y, double yaw) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() << x, y, 0.0;
    T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return T;
}

// The reference: a 40 m x 30 m rectangle's three sides (40 + 30 + 40 = 110 m) in 1 m steps.
AssociatedPoses ThreeSides(const std::function<Eigen::Isometry3d(const Eigen::Isometry3d &)> &est) {
    AssociatedPoses poses;
    std::vector<Eigen::Isometry3d> ref;
    for (int k = 0; k <= 40; ++k) ref.push_back(Pose(k, 0.0, 0.0));
    for (int k = 1; k <= 30; ++k) ref.push_back(Pose(40.0, k, M_PI / 2));
    for (int k = 1; k <= 40; ++k) ref.push_back(Pose(40.0 - k, 30.0, M_PI));
    for (std::size_t k = 0; k < ref.size(); ++k) {
        poses.stamps_ns.push_back(static_cast<int64_t>(k) * 100'000'000LL);
        poses.T_world_ref.push_back(ref[k]);
        poses.T_world_est.push_back(est(ref[k]));
    }
    return poses;
}

TEST(EndPointError, PerfectEstimateHasNoError) {
    const EndPointError e = ComputeEndPointError(ThreeSides([](const auto &T) { return T; }));
    EXPECT_NEAR(e.path_length_m, 110.0, 1e-9);
    EXPECT_NEAR(e.error_m, 0.0, 1e-9);
    EXPECT_NEAR(e.percent, 0.0, 1e-9);
}

TEST(EndPointError, ScaledPathEndsTwoPercentOfItsOffsetAway) {
    // Every position 2 % further from the origin: the end (0, 30) lands at (0, 30.6): 0.6 m,
    // 0.6 / 110 of the path.
    const EndPointError e = ComputeEndPointError(ThreeSides([](const Eigen::Isometry3d &T) {
        Eigen::Isometry3d S = T;
        S.translation() *= 1.02;
        return S;
    }));
    EXPECT_NEAR(e.error_m, 0.6, 1e-9);
    EXPECT_NEAR(e.percent, 100.0 * 0.6 / 110.0, 1e-9);
}

TEST(EndPointError, OtherWorldFrameIsRemovedByTheStartAlignment) {
    // The same path written in a world turned 30 deg and shifted: no error.
    const Eigen::Isometry3d W = Pose(5.0, -7.0, DegToRad(30.0));
    const EndPointError e = ComputeEndPointError(ThreeSides([&](const auto &T) { return W * T; }));
    EXPECT_NEAR(e.error_m, 0.0, 1e-9);
}

TEST(EndPointError, HeadingErrorAfterTheStartSwingsTheEnd) {
    // The estimate turns 1 deg more at the first corner: the last 70 m of path turned 1 deg about
    // the corner (40, 0). The end (0, 30) is at (-40, 30) from the corner; turned by 1 deg it is
    // off by 2 |(-40, 30)| sin(0.5 deg) = 100 sin(0.5 deg).
    const double a = DegToRad(1.0);
    const EndPointError e = ComputeEndPointError(ThreeSides([&](const Eigen::Isometry3d &T) {
        if (T.translation().y() == 0.0) return T;  // the first side, up to the corner
        return Pose(40.0, 0.0, a) * Pose(-40.0, 0.0, 0.0) * T;
    }));
    EXPECT_NEAR(e.error_m, 100.0 * std::sin(a / 2.0), 1e-9);
}

TEST(EndPointError, RefusesASinglePose) {
    AssociatedPoses one;
    one.stamps_ns = {0};
    one.T_world_ref = {Eigen::Isometry3d::Identity()};
    one.T_world_est = {Eigen::Isometry3d::Identity()};
    EXPECT_THROW((void)ComputeEndPointError(one), std::invalid_argument);
}

}  // namespace
}  // namespace dorado::eval
