// SO(3)/SE(3) maps against closed forms written independently here.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dorado/core/lie.hpp"

namespace dorado {
namespace {

Eigen::Matrix3d Rz(double a) {
    Eigen::Matrix3d R;
    R << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
    return R;
}

TEST(Lie, ExpSO3AboutZIsThePlanarRotation) {
    for (const double a : {-3.0, -1.0, 1e-9, 0.3, 2.5, M_PI - 1e-6}) {
        EXPECT_LT((ExpSO3(Eigen::Vector3d(0, 0, a)) - Rz(a)).norm(), 1e-12) << a;
    }
}

TEST(Lie, LogSO3InvertsExpIncludingNearZeroAndPi) {
    std::mt19937 rng(7);
    std::normal_distribution<double> normal;
    for (int k = 0; k < 200; ++k) {
        Eigen::Vector3d axis(normal(rng), normal(rng), normal(rng));
        axis.normalize();
        for (const double angle : {1e-10, 1e-5, 0.1, 1.0, 3.0, M_PI - 1e-7}) {
            const Eigen::Vector3d phi = angle * axis;
            const Eigen::Vector3d back = LogSO3(ExpSO3(phi));
            EXPECT_LT((back - phi).norm(), 1e-6 * std::max(1.0, angle)) << angle;
            EXPECT_NEAR(RotationAngle(ExpSO3(phi)), angle, 1e-6);
        }
    }
}

TEST(Lie, HatIsTheCrossProduct) {
    const Eigen::Vector3d a(1, -2, 3), b(0.5, 4, -1);
    EXPECT_LT((Hat(a) * b - a.cross(b)).norm(), 1e-15);
}

TEST(Lie, ExpSE3OfAConstantTwistIsTheScrewMotion) {
    // Body moving at v along x while yawing at w for 1 s: a circle arc of radius v/w.
    const double v = 2.0, w = 0.5;
    Vector6d xi;
    xi << v, 0, 0, 0, 0, w;
    const Eigen::Isometry3d T = ExpSE3(xi);
    const double r = v / w;
    EXPECT_NEAR(T.translation().x(), r * std::sin(w), 1e-12);
    EXPECT_NEAR(T.translation().y(), r * (1 - std::cos(w)), 1e-12);
    EXPECT_NEAR(T.translation().z(), 0.0, 1e-12);
    EXPECT_LT((T.linear() - Rz(w)).norm(), 1e-12);
}

TEST(Lie, ExpSE3MatchesManySmallSteps) {
    Vector6d xi;
    xi << 1.0, -0.3, 0.2, 0.1, -0.4, 0.7;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    const int steps = 100000;
    for (int i = 0; i < steps; ++i) {
        Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
        step.linear() = ExpSO3(xi.tail<3>() / steps);
        step.translation() = xi.head<3>() / steps;
        T = T * step;
    }
    EXPECT_LT((T.matrix() - ExpSE3(xi).matrix()).norm(), 1e-4);
}

TEST(Lie, LogSE3InvertsExpSE3) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    for (int k = 0; k < 200; ++k) {
        Vector6d xi;
        for (int j = 0; j < 6; ++j) xi[j] = u(rng);
        if (xi.tail<3>().norm() > 3.0) continue;
        EXPECT_LT((LogSE3(ExpSE3(xi)) - xi).norm(), 1e-9);
    }
}

TEST(Lie, LeftJacobianInverseIsTheInverse) {
    const Eigen::Vector3d phi(0.3, -1.2, 0.8);
    EXPECT_LT(
        (LeftJacobianSO3(phi) * LeftJacobianInverseSO3(phi) - Eigen::Matrix3d::Identity()).norm(),
        1e-12);
}

TEST(Lie, InterpolatePoseHalfwayIsHalfTheAngleAndTheMidpoint) {
    Eigen::Isometry3d a = Eigen::Isometry3d::Identity(), b = Eigen::Isometry3d::Identity();
    a.translation() << 1, 2, 3;
    b.linear() = Rz(1.2);
    b.translation() << 3, 2, -1;
    const Eigen::Isometry3d mid = InterpolatePose(a, b, 0.5);
    EXPECT_LT((mid.linear() - Rz(0.6)).norm(), 1e-12);
    EXPECT_LT((mid.translation() - Eigen::Vector3d(2, 2, 1)).norm(), 1e-12);
    EXPECT_LT((InterpolatePose(a, b, 0.0).matrix() - a.matrix()).norm(), 1e-12);
    EXPECT_LT((InterpolatePose(a, b, 1.0).matrix() - b.matrix()).norm(), 1e-12);
}

}  // namespace
}  // namespace dorado
