// The refinement's Ceres functors: analytic Jacobians (autodiff) against numeric differences with
// ceres::GradientChecker, and residual values against independent formulas.
#include <ceres/gradient_checker.h>
#include <ceres/manifold.h>
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "cost_functions.hpp"
#include "dorado/core/lie.hpp"
#include "whitening.hpp"

namespace dorado::mapping {
namespace {

Eigen::Isometry3d Pose(const Vector6d &xi) {
    return ExpSE3(xi);
}

Vector6d Xi(double a, double b, double c, double d, double e, double f) {
    Vector6d xi;
    xi << a, b, c, d, e, f;
    return xi;
}

// Runs GradientChecker on a (p: 3, q: 4 with EigenQuaternionManifold) functor at T.
void ExpectGradientsMatch(const ceres::CostFunction &cost, const Eigen::Isometry3d &T) {
    Eigen::Vector3d p = T.translation();
    Eigen::Quaterniond q(T.linear());
    ceres::EigenQuaternionManifold quaternion_manifold;
    std::vector<const ceres::Manifold *> manifolds{nullptr, &quaternion_manifold};
    ceres::NumericDiffOptions numeric_options;
    ceres::GradientChecker checker(&cost, &manifolds, numeric_options);
    std::vector<const double *> parameters{p.data(), q.coeffs().data()};
    ceres::GradientChecker::ProbeResults results;
    EXPECT_TRUE(checker.Probe(parameters.data(), 1e-7, &results)) << results.error_log;
}

// The registration residual written the plain way, differentiated by Ceres: the analytic Jacobians
// must be what automatic differentiation gives, in the raw 4-vector quaternion coordinates too.
struct AutoDiffRegistration {
    Eigen::Vector3d p_base, q_world;
    Eigen::Matrix3d W;
    template <typename T>
    bool operator()(const T *const p_ptr, const T *const q_ptr, T *r_ptr) const {
        Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(p_ptr);
        Eigen::Map<const Eigen::Quaternion<T>> q(q_ptr);
        Eigen::Map<Eigen::Matrix<T, 3, 1>> r(r_ptr);
        r = W.cast<T>() * (q * p_base.cast<T>() + t - q_world.cast<T>());
        return true;
    }
};

TEST(CostFunctions, RegistrationErrorAnalyticJacobiansEqualAutomaticDifferentiation) {
    const Eigen::Vector3d p_base(5.0, 2.3, -1.7), q_world(1.0, 2.0, 3.0);
    const Eigen::Matrix3d W = ExpSO3(Eigen::Vector3d(0.3, -0.2, 0.5)) * 3.0;
    std::unique_ptr<ceres::CostFunction> analytic(RegistrationError::Create(p_base, q_world, W));
    ceres::AutoDiffCostFunction<AutoDiffRegistration, 3, 3, 4> automatic(
        new AutoDiffRegistration{p_base, q_world, W});
    for (const auto &T : {Pose(Xi(3.0, -1.0, 0.5, 0.1, -0.2, 0.7)), Pose(Xi(0, 0, 0, 0, 0, 0)),
                          Pose(Xi(-2.0, 4.0, 1.0, 2.5, 0.3, -1.0))}) {
        Eigen::Vector3d p = T.translation();
        Eigen::Quaterniond q(T.linear());
        const double *params[] = {p.data(), q.coeffs().data()};
        double r_a[3], r_b[3], jt_a[9], jt_b[9], jq_a[12], jq_b[12];
        double *jac_a[] = {jt_a, jq_a}, *jac_b[] = {jt_b, jq_b};
        ASSERT_TRUE(analytic->Evaluate(params, r_a, jac_a));
        ASSERT_TRUE(automatic.Evaluate(params, r_b, jac_b));
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(r_a[i], r_b[i], 1e-12);
        for (int i = 0; i < 9; ++i) EXPECT_NEAR(jt_a[i], jt_b[i], 1e-12);
        for (int i = 0; i < 12; ++i) EXPECT_NEAR(jq_a[i], jq_b[i], 1e-11) << i;
    }
}

TEST(CostFunctions, RegistrationErrorGradientAndValue) {
    const Eigen::Isometry3d T = Pose(Xi(3.0, -1.0, 0.5, 0.1, -0.2, 0.7));
    const Eigen::Vector3d p_base(5.0, 2.3, -1.7), q_world(1.0, 2.0, 3.0);
    Eigen::Matrix3d C;
    C << 0.09, 0.01, 0.0, 0.01, 0.04, 0.005, 0.0, 0.005, 0.02;
    // Any Q L^-1 (Q orthogonal) whitens too; a full matrix avoids structural zeros in the
    // Jacobian, which GradientChecker's relative error cannot judge.
    const Eigen::Matrix3d W = ExpSO3(Eigen::Vector3d(0.3, -0.2, 0.5)) * InverseCholeskyFactor<3>(C);
    std::unique_ptr<ceres::CostFunction> cost(RegistrationError::Create(p_base, q_world, W));
    ExpectGradientsMatch(*cost, T);

    // Value: |r|^2 is the Mahalanobis norm of e = T p - q under C.
    Eigen::Vector3d p = T.translation();
    Eigen::Quaterniond q(T.linear());
    const double *params[] = {p.data(), q.coeffs().data()};
    Eigen::Vector3d r;
    ASSERT_TRUE(cost->Evaluate(params, r.data(), nullptr));
    const Eigen::Vector3d e = T * p_base - q_world;
    EXPECT_NEAR(r.squaredNorm(), e.dot(C.inverse() * e), 1e-9);
}

TEST(CostFunctions, DopplerErrorIsZeroForTheTrueTwistAndHasCorrectGradients) {
    // Constant twist over dt from T_prev: the Doppler of a static point seen at the new pose.
    const Eigen::Isometry3d T_prev = Pose(Xi(10.0, 4.0, 0.3, 0.02, -0.01, 1.2));
    const Eigen::Vector3d v_base(8.0, 0.3, -0.1), omega_base(0.03, -0.02, 0.4);
    const double dt = 0.1;
    Vector6d xi;
    xi << v_base * dt, omega_base * dt;
    const Eigen::Isometry3d T = T_prev * ExpSE3(xi);
    const Eigen::Isometry3d T_base_radar = Pose(Xi(1.2, 0.1, 0.8, 0.0, 0.05, -0.3));
    const Eigen::Vector3d v_radar =
        T_base_radar.linear().transpose() * (v_base + omega_base.cross(T_base_radar.translation()));
    const Eigen::Vector3d d = Eigen::Vector3d(0.8, -0.5, 0.2).normalized();
    const double doppler = -d.dot(v_radar);  // paper eq. (1)
    const double sigma = 0.1;

    std::unique_ptr<ceres::CostFunction> exact(
        DopplerError::Create(d, doppler, T_base_radar, T_prev, dt, sigma));
    Eigen::Vector3d p = T.translation();
    Eigen::Quaterniond q(T.linear());
    const double *params[] = {p.data(), q.coeffs().data()};
    double r = 1.0;
    ASSERT_TRUE(exact->Evaluate(params, &r, nullptr));
    EXPECT_NEAR(r, 0.0, 1e-9);

    // A measurement 0.05 m/s off gives exactly 0.05 / sigma.
    std::unique_ptr<ceres::CostFunction> off(
        DopplerError::Create(d, doppler + 0.05, T_base_radar, T_prev, dt, sigma));
    ASSERT_TRUE(off->Evaluate(params, &r, nullptr));
    EXPECT_NEAR(r, 0.5, 1e-9);

    ExpectGradientsMatch(*exact, T);
    // Also at zero rotation between the poses (the small-angle branches).
    const Eigen::Isometry3d T_straight = T_prev * ExpSE3(Xi(0.8, 0.0, 0.0, 0.0, 0.0, 0.0));
    ExpectGradientsMatch(*exact, T_straight);
}

// The refinement shares one pose velocity among all Doppler residuals: interleaved evaluations at
// different poses, with and without Jacobians, must give what independent residuals give.
TEST(CostFunctions, SharedVelocityGivesWhatIndependentResidualsGive) {
    const Eigen::Isometry3d T_prev = Pose(Xi(1.0, 2.0, 0.1, 0.01, 0.02, 0.3));
    const Eigen::Isometry3d T_base_radar = Pose(Xi(1.5, -0.1, 0.9, 0.0, 0.1, 0.2));
    const double dt = 0.08, sigma = 0.1;
    const auto shared = std::make_shared<SharedRadarVelocity>(T_base_radar, T_prev, dt);
    const Eigen::Vector3d d1 = Eigen::Vector3d(0.9, 0.3, 0.1).normalized();
    const Eigen::Vector3d d2 = Eigen::Vector3d(0.2, -0.9, 0.3).normalized();
    const DopplerError a(d1, 1.5, shared, sigma), b(d2, -0.7, shared, sigma);
    std::unique_ptr<ceres::CostFunction> a_alone(
        DopplerError::Create(d1, 1.5, T_base_radar, T_prev, dt, sigma));
    std::unique_ptr<ceres::CostFunction> b_alone(
        DopplerError::Create(d2, -0.7, T_base_radar, T_prev, dt, sigma));
    const Eigen::Isometry3d poses[] = {T_prev * Pose(Xi(0.9, 0.05, 0.0, 0.0, 0.01, 0.05)),
                                       T_prev * Pose(Xi(0.7, -0.02, 0.01, 0.01, 0.0, -0.1))};
    int k = 0;
    for (const auto &T : {poses[0], poses[1], poses[0], poses[1]}) {
        Eigen::Vector3d p = T.translation();
        Eigen::Quaterniond q(T.linear());
        const double *params[] = {p.data(), q.coeffs().data()};
        for (const auto &[shared_cost, alone] :
             {std::pair<const ceres::CostFunction *, const ceres::CostFunction *>{&a,
                                                                                  a_alone.get()},
              {&b, b_alone.get()}}) {
            double r_shared, r_alone, jp_s[3], jq_s[4], jp_a[3], jq_a[4];
            double *jac_s[] = {jp_s, jq_s}, *jac_a[] = {jp_a, jq_a};
            const bool with_jacobians = (k++ % 3) != 0;
            ASSERT_TRUE(shared_cost->Evaluate(params, &r_shared, with_jacobians ? jac_s : nullptr));
            ASSERT_TRUE(alone->Evaluate(params, &r_alone, jac_a));
            EXPECT_DOUBLE_EQ(r_shared,
                             r_alone);  // the Jet and double paths may differ in the last bit
            if (!with_jacobians) continue;
            for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(jp_s[i], jp_a[i]);
            for (int i = 0; i < 4; ++i) EXPECT_DOUBLE_EQ(jq_s[i], jq_a[i]);
        }
    }
}

TEST(CostFunctions, LogHelpersMatchCoreLie) {
    const Vector6d xi = Xi(0.7, -0.3, 0.2, 0.3, -0.5, 0.9);
    const Eigen::Isometry3d T = ExpSE3(xi);
    const Eigen::Vector3d phi = RadarVelocityOfPose::LogQuaternion(Eigen::Quaterniond(T.linear()));
    const Eigen::Vector3d rho =
        RadarVelocityOfPose::LeftJacobianInverseTimes<double>(phi, T.translation());
    EXPECT_LT((phi - xi.tail<3>()).norm(), 1e-12);
    EXPECT_LT((rho - xi.head<3>()).norm(), 1e-12);
}

TEST(CostFunctions, PriorErrorIsWhitenedByTheCovariance) {
    const Eigen::Isometry3d T_prior = Pose(Xi(2.0, 1.0, 0.0, 0.0, 0.0, 0.5));
    std::mt19937 rng(3);
    std::normal_distribution<double> n(0.0, 1.0);
    Matrix6d A;
    for (int i = 0; i < 36; ++i) A(i / 6, i % 6) = n(rng);
    const Matrix6d C = 0.01 * (A * A.transpose() + Matrix6d::Identity());
    std::unique_ptr<ceres::CostFunction> cost(
        PriorError::Create(T_prior, InverseCholeskyFactor<6>(C)));

    const Vector6d small = Xi(1e-3, -2e-3, 5e-4, 1e-3, 2e-3, -1e-3);
    const Eigen::Isometry3d T = T_prior * ExpSE3(small);
    Eigen::Vector3d p = T.translation();
    Eigen::Quaterniond q(T.linear());
    const double *params[] = {p.data(), q.coeffs().data()};
    Vector6d r;
    ASSERT_TRUE(cost->Evaluate(params, r.data(), nullptr));
    // To first order r^T r = xi^T C^-1 xi (the residual is [delta_p; 2 vec(delta_q)] ~ xi).
    const double mahalanobis = small.dot(C.ldlt().solve(small));
    EXPECT_NEAR(r.squaredNorm(), mahalanobis, 1e-3 * mahalanobis);
    ExpectGradientsMatch(*cost, T);
}

}  // namespace
}  // namespace dorado::mapping
