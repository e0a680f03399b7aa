// The pose graph's Ceres functors: Jacobians against numeric differences (ceres::GradientChecker)
// on the quaternion manifold, and residual values against LogSE3 of the pose error.
#include <ceres/gradient_checker.h>
#include <ceres/manifold.h>
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "dorado/core/lie.hpp"
#include "pose_graph_residuals.hpp"

namespace dorado::loops {
namespace {

Vector6d Xi(double a, double b, double c, double d, double e, double f) {
    return (Vector6d() << a, b, c, d, e, f).finished();
}

// A positive definite, non-diagonal information's whitening factor.
Matrix6d SomeSqrtInformation() {
    Matrix6d A = Matrix6d::Identity() * 2.0;
    A(0, 4) = 0.3;
    A(1, 5) = -0.2;
    A(2, 3) = 0.1;
    return SqrtInformation(A * A.transpose());
}

struct Node {
    Eigen::Vector3d p;
    Eigen::Quaterniond q;
    explicit Node(const Eigen::Isometry3d &T) : p(T.translation()), q(T.rotation()) {}
};

void ExpectGradientsMatch(const ceres::CostFunction &cost, std::vector<const double *> parameters,
                          bool with_switch) {
    ceres::EigenQuaternionManifold quaternion;
    std::vector<const ceres::Manifold *> manifolds{nullptr, &quaternion, nullptr, &quaternion};
    if (with_switch) manifolds.push_back(nullptr);
    ceres::NumericDiffOptions numeric_options;
    ceres::GradientChecker checker(&cost, &manifolds, numeric_options);
    ceres::GradientChecker::ProbeResults results;
    EXPECT_TRUE(checker.Probe(parameters.data(), 1e-7, &results)) << results.error_log;
}

const Eigen::Isometry3d kTworldA = ExpSE3(Xi(1.0, -2.0, 0.5, 0.2, -0.1, 0.8));
const Eigen::Isometry3d kTworldB = ExpSE3(Xi(12.0, 3.0, -0.4, -0.05, 0.15, 2.1));
const Eigen::Isometry3d kTabMeasured = ExpSE3(Xi(9.0, 6.0, 0.1, 0.1, 0.0, 1.2));

TEST(PoseGraphResiduals, PoseGraph3dErrorTermJacobiansMatchNumericDifferences) {
    std::unique_ptr<ceres::CostFunction> cost(
        PoseGraph3dErrorTerm::Create(kTabMeasured, SomeSqrtInformation()));
    Node a(kTworldA), b(kTworldB);
    ExpectGradientsMatch(*cost, {a.p.data(), a.q.coeffs().data(), b.p.data(), b.q.coeffs().data()},
                         false);
}

TEST(PoseGraphResiduals, SwitchableLoopErrorTermJacobiansMatchNumericDifferences) {
    std::unique_ptr<ceres::CostFunction> cost(
        SwitchableLoopErrorTerm::Create(kTabMeasured, SomeSqrtInformation()));
    Node a(kTworldA), b(kTworldB);
    double s = 0.7;
    ExpectGradientsMatch(
        *cost, {a.p.data(), a.q.coeffs().data(), b.p.data(), b.q.coeffs().data(), &s}, true);
}

TEST(PoseGraphResiduals, SwitchPriorErrorTermJacobianMatchesNumericDifferences) {
    std::unique_ptr<ceres::CostFunction> cost(SwitchPriorErrorTerm::Create(0.5));
    double s = 0.3;
    std::vector<const double *> parameters{&s};
    ceres::NumericDiffOptions numeric_options;
    const std::vector<const ceres::Manifold *> no_manifold{nullptr};
    ceres::GradientChecker checker(cost.get(), &no_manifold, numeric_options);
    ceres::GradientChecker::ProbeResults results;
    EXPECT_TRUE(checker.Probe(parameters.data(), 1e-7, &results)) << results.error_log;
    double residual = 0.0;
    const double *blocks[] = {&s};
    ASSERT_TRUE(cost->Evaluate(blocks, &residual, nullptr));
    EXPECT_NEAR(residual, (1.0 - 0.3) / 0.5, 1e-12);
}

// The error is the right perturbation of b: with T_world_b = T_world_a T_ab ExpSE3(xi), the
// unwhitened residual is xi up to second order terms (and exactly zero at xi = 0).
TEST(PoseGraphResiduals, ErrorIsTheRightPerturbationOfTheLaterNode) {
    std::unique_ptr<ceres::CostFunction> cost(
        PoseGraph3dErrorTerm::Create(kTabMeasured, Matrix6d::Identity()));
    for (const Vector6d &xi :
         {Vector6d(Vector6d::Zero()), Xi(0.01, -0.02, 0.005, 0.002, -0.001, 0.003),
          Xi(-0.03, 0.0, 0.01, 0.0, 0.004, -0.002)}) {
        Node a(kTworldA), b(kTworldA * kTabMeasured * ExpSE3(xi));
        const double *blocks[] = {a.p.data(), a.q.coeffs().data(), b.p.data(), b.q.coeffs().data()};
        Vector6d residual;
        ASSERT_TRUE(cost->Evaluate(blocks, residual.data(), nullptr));
        EXPECT_LT((residual - xi).norm(), xi.squaredNorm() + 1e-12) << xi.transpose();
    }
}

// Whitening: r^T r = xi^T Lambda xi.
TEST(PoseGraphResiduals, WhitenedResidualGivesTheMahalanobisNorm) {
    const Matrix6d U = SomeSqrtInformation();
    const Matrix6d information = U.transpose() * U;
    std::unique_ptr<ceres::CostFunction> cost(PoseGraph3dErrorTerm::Create(kTabMeasured, U));
    const Vector6d xi = Xi(1e-4, -2e-4, 3e-4, 1e-5, 2e-5, -1e-5);
    Node a(kTworldA), b(kTworldA * kTabMeasured * ExpSE3(xi));
    const double *blocks[] = {a.p.data(), a.q.coeffs().data(), b.p.data(), b.q.coeffs().data()};
    Vector6d residual;
    ASSERT_TRUE(cost->Evaluate(blocks, residual.data(), nullptr));
    EXPECT_NEAR(residual.squaredNorm(), xi.dot(information * xi), 1e-3 * xi.dot(information * xi));
}

}  // namespace
}  // namespace dorado::loops
