// The window smoother's factors: analytic Jacobians against numeric differences with
// ceres::GradientChecker, residual values against independent computations (finite differences of
// a rigid motion, a simulated random walk).
#include <ceres/gradient_checker.h>
#include <ceres/manifold.h>
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "dorado/core/lie.hpp"
#include "window_factors.hpp"

namespace dorado::mapping {
namespace {

Vector6d Xi(double a, double b, double c, double d, double e, double f) {
    Vector6d xi;
    xi << a, b, c, d, e, f;
    return xi;
}

void ExpectGradientsMatch(const ceres::CostFunction &cost, std::vector<double *> blocks,
                          const std::vector<const ceres::Manifold *> &manifolds) {
    ceres::NumericDiffOptions numeric_options;
    ceres::GradientChecker checker(&cost, &manifolds, numeric_options);
    std::vector<const double *> parameters(blocks.begin(), blocks.end());
    ceres::GradientChecker::ProbeResults results;
    EXPECT_TRUE(checker.Probe(parameters.data(), 1e-7, &results)) << results.error_log;
}

// Velocity (world frame) of a body-fixed point p_body at t = 0 under T(t) = T0 ExpSE3(t xi), by
// central differences: independent of the v + w x p formula the factors use.
Eigen::Vector3d PointVelocityWorld(const Eigen::Isometry3d &T0, const Vector6d &xi,
                                   const Eigen::Vector3d &p_body) {
    const double h = 1e-6;
    return ((T0 * ExpSE3(h * xi)) * p_body - (T0 * ExpSE3(-h * xi)) * p_body) / (2.0 * h);
}

const Eigen::Isometry3d kT0 = ExpSE3(Xi(10.0, 4.0, 0.3, 0.02, -0.01, 1.2));
const Eigen::Isometry3d kTBaseRadar = ExpSE3(Xi(1.2, 0.1, 0.8, 0.0, 0.05, -0.3));

TEST(WindowFactors, TwistDopplerMatchesFiniteDifferencesAndGradients) {
    Eigen::Vector3d v(8.0, 0.3, -0.1), w(0.03, -0.02, 0.4);
    const Vector6d xi = (Vector6d() << v, w).finished();
    const Eigen::Vector3d v_radar_world = PointVelocityWorld(kT0, xi, kTBaseRadar.translation());
    const Eigen::Vector3d v_radar = (kT0 * kTBaseRadar).linear().transpose() * v_radar_world;
    const Eigen::Vector3d d = Eigen::Vector3d(0.8, -0.5, 0.2).normalized();
    const double sigma = 0.1;
    TwistDopplerError exact(d, -d.dot(v_radar), kTBaseRadar, sigma);  // paper eq. (1)
    TwistDopplerError off(d, -d.dot(v_radar) + 0.05, kTBaseRadar, sigma);
    const double *params[] = {v.data(), w.data()};
    double r = 1.0;
    ASSERT_TRUE(exact.Evaluate(params, &r, nullptr));
    EXPECT_NEAR(r, 0.0, 1e-6);
    ASSERT_TRUE(off.Evaluate(params, &r, nullptr));
    EXPECT_NEAR(r, 0.5, 1e-6);
    ExpectGradientsMatch(exact, {v.data(), w.data()}, {nullptr, nullptr});
}

TEST(WindowFactors, KinematicErrorIsTheViolationOfEquations3And4) {
    const double m = 1.4;
    const Eigen::Vector3d sigmas(0.02, 0.05, 0.1);
    Eigen::Vector3d v(8.0, 0.3, -0.1), w(0.03, -0.02, 0.4);
    const Vector6d xi = (Vector6d() << v, w).finished();
    // The rear axle's lateral velocity, the Y-ICR point's vertical velocity (base frame), roll.
    const Eigen::Matrix3d R0_T = kT0.linear().transpose();
    const double lateral = (R0_T * PointVelocityWorld(kT0, xi, Eigen::Vector3d(0.0, 0.0, 0.0))).y();
    const double vertical = (R0_T * PointVelocityWorld(kT0, xi, Eigen::Vector3d(m, 0.0, 0.7))).z();
    KinematicError cost(m, sigmas);
    const double *params[] = {v.data(), w.data()};
    Eigen::Vector3d r;
    ASSERT_TRUE(cost.Evaluate(params, r.data(), nullptr));
    EXPECT_NEAR(r(0), lateral / sigmas(0), 1e-6);
    EXPECT_NEAR(r(1), vertical / sigmas(1), 1e-6);
    EXPECT_NEAR(r(2), w.x() / sigmas(2), 1e-12);
    // A twist that obeys the model (eq. 5: v_y = 0, v_z = m w_y, w_x = 0) has no residual.
    Eigen::Vector3d v_ok(8.0, 0.0, m * -0.02), w_ok(0.0, -0.02, 0.4);
    const double *params_ok[] = {v_ok.data(), w_ok.data()};
    ASSERT_TRUE(cost.Evaluate(params_ok, r.data(), nullptr));
    EXPECT_NEAR(r.norm(), 0.0, 1e-12);
    ExpectGradientsMatch(cost, {v.data(), w.data()}, {nullptr, nullptr});
}

TEST(WindowFactors, GyroErrorAndBiasPrior) {
    Eigen::Vector3d w(0.03, -0.02, 0.4), b(0.001, 0.002, -0.003);
    const Eigen::Vector3d gyro = w + b + Eigen::Vector3d(0.01, 0.0, -0.02);
    GyroError cost(gyro, 0.01);
    const double *params[] = {w.data(), b.data()};
    Eigen::Vector3d r;
    ASSERT_TRUE(cost.Evaluate(params, r.data(), nullptr));
    EXPECT_NEAR((r - Eigen::Vector3d(1.0, 0.0, -2.0)).norm(), 0.0, 1e-9);
    ExpectGradientsMatch(cost, {w.data(), b.data()}, {nullptr, nullptr});
    VectorPriorError prior(Eigen::Vector3d::Zero(), 0.001);
    const double *params_b[] = {b.data()};
    ASSERT_TRUE(prior.Evaluate(params_b, r.data(), nullptr));
    EXPECT_NEAR((r - Eigen::Vector3d(1.0, 2.0, -3.0)).norm(), 0.0, 1e-9);
    ExpectGradientsMatch(prior, {b.data()}, {nullptr});
}

struct WnoaStates {
    Eigen::Vector3d p_i, v_i, w_i, p_j, v_j, w_j;
    Eigen::Quaterniond q_i, q_j;
    std::vector<double *> Blocks() {
        return {p_i.data(), q_i.coeffs().data(), v_i.data(), w_i.data(),
                p_j.data(), q_j.coeffs().data(), v_j.data(), w_j.data()};
    }
};

WnoaStates ConstantTwist(const Eigen::Vector3d &v, const Eigen::Vector3d &w, double dt) {
    const Eigen::Isometry3d T_j = kT0 * ExpSE3((Vector6d() << v * dt, w * dt).finished());
    return {kT0.translation(),
            v,
            w,
            T_j.translation(),
            v,
            w,
            Eigen::Quaterniond(kT0.linear()),
            Eigen::Quaterniond(T_j.linear())};
}

TEST(WindowFactors, WnoaIsNearZeroOnAConstantTwistAndHasCorrectGradients) {
    const double dt = 0.1;
    const Eigen::Matrix<double, 6, 1> qc =
        (Eigen::Matrix<double, 6, 1>() << 1.0, 0.1, 0.1, 0.01, 0.01, 0.1).finished();
    WnoaError cost(dt, qc);
    WnoaStates x =
        ConstantTwist(Eigen::Vector3d(8.0, 0.3, -0.1), Eigen::Vector3d(0.03, -0.02, 0.4), dt);
    std::vector<double *> blocks = x.Blocks();
    std::vector<const double *> params(blocks.begin(), blocks.end());
    Eigen::Matrix<double, 12, 1> r;
    ASSERT_TRUE(cost.Evaluate(params.data(), r.data(), nullptr));
    // Exact to second order: the left-over dt^3/6 w x (w x v) ~ 0.2 mm is < 0.1 sigma whitened.
    EXPECT_LT(r.norm(), 0.1);

    // -q_j is the same rotation: the same residual.
    WnoaStates flipped = x;
    flipped.q_j.coeffs() = -flipped.q_j.coeffs();
    blocks = flipped.Blocks();
    params.assign(blocks.begin(), blocks.end());
    Eigen::Matrix<double, 12, 1> r_flipped;
    ASSERT_TRUE(cost.Evaluate(params.data(), r_flipped.data(), nullptr));
    EXPECT_NEAR((r_flipped - r).norm(), 0.0, 1e-9);

    // One extra centimetre forward on the second pose: e_t = R_i^T (1, 0, 0) world = that in base
    // i.
    WnoaStates moved = x;
    moved.p_j += kT0.linear() * Eigen::Vector3d(0.01, 0.0, 0.0);
    blocks = moved.Blocks();
    params.assign(blocks.begin(), blocks.end());
    Eigen::Matrix<double, 12, 1> r_moved;
    ASSERT_TRUE(cost.Evaluate(params.data(), r_moved.data(), nullptr));
    Eigen::Matrix<double, 12, 1> e = Eigen::Matrix<double, 12, 1>::Zero();
    e(0) = 0.01;
    const Eigen::Matrix<double, 12, 12> Q = WnoaError::Covariance(dt, qc);
    const double expected = e.dot(Q.inverse() * e);
    EXPECT_NEAR((r_moved - r).dot(r_moved - r), expected, 1e-6 * expected);

    ceres::EigenQuaternionManifold qm;
    WnoaStates perturbed = x;  // away from zero residual, where GradientChecker is meaningful
    perturbed.v_j += Eigen::Vector3d(0.3, -0.2, 0.1);
    perturbed.w_i += Eigen::Vector3d(0.05, 0.02, -0.04);
    perturbed.p_j += Eigen::Vector3d(0.2, 0.1, -0.3);
    ExpectGradientsMatch(cost, perturbed.Blocks(),
                         {nullptr, &qm, nullptr, nullptr, nullptr, &qm, nullptr, nullptr});
    perturbed.q_i.coeffs() = -perturbed.q_i.coeffs();  // the w < 0 branch
    ExpectGradientsMatch(cost, perturbed.Blocks(),
                         {nullptr, &qm, nullptr, nullptr, nullptr, &qm, nullptr, nullptr});
}

// Q against a simulated white-noise acceleration of PSD qc: the covariance of
// [p(dt) - dt v(0); v(dt) - v(0)] is qc [dt^3/3, dt^2/2; dt^2/2, dt].
TEST(WindowFactors, WnoaCovarianceIsThatOfASimulatedRandomWalk) {
    const double dt = 0.1, qc = 2.0;
    const int steps = 200, trials = 20000;
    const double h = dt / steps;
    std::mt19937 rng(7);
    std::normal_distribution<double> accel(0.0, std::sqrt(qc / h));
    Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
    for (int k = 0; k < trials; ++k) {
        double p = 0.0, v = 0.0;
        for (int s = 0; s < steps; ++s) {
            const double a = accel(rng);
            p += v * h + 0.5 * a * h * h;
            v += a * h;
        }
        const Eigen::Vector2d e(p, v);
        C += e * e.transpose() / trials;
    }
    const Eigen::Matrix<double, 12, 12> Q =
        WnoaError::Covariance(dt, Eigen::Matrix<double, 6, 1>::Constant(qc));
    EXPECT_NEAR(C(0, 0), Q(0, 0), 0.05 * Q(0, 0));
    EXPECT_NEAR(C(0, 1), Q(0, 6), 0.05 * Q(0, 6));
    EXPECT_NEAR(C(1, 1), Q(6, 6), 0.05 * Q(6, 6));
}

}  // namespace
}  // namespace dorado::mapping
