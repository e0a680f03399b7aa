// The registration's covariance (pose_information.hpp) against independent truths: the right-
// perturbation lift against numeric differences, the independent model against a Monte Carlo of
// least-squares registrations with known noise, and the clustered model counting residuals that
// share one error as one measurement.
#include <ceres/loss_function.h>
#include <gtest/gtest.h>

#include <random>

#include "dorado/core/lie.hpp"
#include "dorado/mapping/radar_mapper.hpp"
#include "pose_information.hpp"

namespace dorado::mapping {
namespace {

// Points spread in a box around the sensor, each a match to itself at the true pose (identity).
std::vector<Eigen::Vector3d> Points(int n, std::mt19937 &rng) {
    std::uniform_real_distribution<double> u(-20.0, 20.0);
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i < n; ++i) points.emplace_back(u(rng), u(rng), 0.2 * u(rng));
    return points;
}

TEST(PoseInformation, LiftIsTheDerivativeOfTheRightPerturbation) {
    const Eigen::Isometry3d T = ExpSE3((Vector6d() << 1.0, -2.0, 0.5, 0.3, -0.2, 0.9).finished());
    const Eigen::Quaterniond q(T.linear());
    const Eigen::Matrix<double, 7, 6> lift = RightPerturbationLift(q);
    const double h = 1e-7;
    for (int k = 0; k < 6; ++k) {
        Vector6d xi = Vector6d::Zero();
        xi(k) = h;
        const Eigen::Isometry3d Tp = T * ExpSE3(xi);
        Eigen::Quaterniond qp(Tp.linear());
        if (qp.coeffs().dot(q.coeffs()) < 0) qp.coeffs() *= -1.0;
        Eigen::Matrix<double, 7, 1> d;
        d << (Tp.translation() - T.translation()) / h, (qp.coeffs() - q.coeffs()) / h;
        EXPECT_LT((d - lift.col(k)).norm(), 1e-5) << "column " << k;
    }
}

// Registration by linearised least squares with independent isotropic noise sigma: its covariance
// is sigma^2 (J^T J)^-1 exactly; the independent model (whitened by 1/sigma) must match the
// Monte Carlo covariance of the estimates (NEES mean 6 within sampling error), and a covariance 4x
// off would not.
TEST(PoseInformation, IndependentModelMatchesMonteCarlo) {
    std::mt19937 rng(7);
    const double sigma = 0.3;
    const std::vector<Eigen::Vector3d> points = Points(200, rng);
    MapperConfig config;
    config.registration_covariance = RegistrationCovarianceModel::kIndependent;
    config.registration_floor_sigma_translation_m = 0.0;
    config.registration_floor_sigma_rotation_rad = 0.0;
    std::vector<Correspondence> matches;
    for (const auto &p : points) matches.push_back({p, p, Eigen::Matrix3d::Identity() / sigma});
    const RegisteredPose model =
        RegistrationCovariance(Eigen::Isometry3d::Identity(), matches, nullptr, config);
    ASSERT_TRUE(model.valid);

    // Monte Carlo: noisy map points, the Gauss-Newton estimate xi = (J^T J)^-1 J^T e.
    std::normal_distribution<double> n(0.0, sigma);
    Eigen::Matrix<double, 6, 6> JtJ = Eigen::Matrix<double, 6, 6>::Zero();
    std::vector<Eigen::Matrix<double, 3, 6>> J(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        J[i] << Eigen::Matrix3d::Identity(), -Hat(points[i]);
        JtJ += J[i].transpose() * J[i];
    }
    double nees = 0.0;
    const int trials = 400;
    for (int t = 0; t < trials; ++t) {
        Vector6d b = Vector6d::Zero();
        for (std::size_t i = 0; i < points.size(); ++i)
            b += J[i].transpose() * Eigen::Vector3d(n(rng), n(rng), n(rng));
        const Vector6d xi = JtJ.ldlt().solve(b);
        nees += xi.dot(model.covariance.ldlt().solve(xi)) / trials;
    }
    // 400 x 6 dof: the mean's 95 % band is about [5.67, 6.34].
    EXPECT_GT(nees, 5.5);
    EXPECT_LT(nees, 6.5);
}

// The same error shared by all residuals of a cluster: the clustered model must see that n copies
// of one measurement are one, the independent model cannot.
TEST(PoseInformation, ClusteredModelCountsSharedErrorsOnce) {
    std::mt19937 rng(11);
    const std::vector<Eigen::Vector3d> points = Points(40, rng);
    std::normal_distribution<double> n(0.0, 0.3);
    std::vector<Correspondence> matches;
    for (const auto &p : points) {
        const Eigen::Vector3d shared(n(rng), n(rng), n(rng));  // the cluster's error
        for (int copy = 0; copy < 10; ++copy)                  // 10 residuals see it
            matches.push_back({p, p + shared, Eigen::Matrix3d::Identity() / 0.3});
    }
    MapperConfig config;
    config.registration_floor_sigma_translation_m = 0.0;
    config.registration_floor_sigma_rotation_rad = 0.0;
    config.registration_cluster_m = 0.01;  // each point its own cell: one cluster per point
    config.registration_covariance = RegistrationCovarianceModel::kIndependent;
    const auto independent =
        RegistrationCovariance(Eigen::Isometry3d::Identity(), matches, nullptr, config);
    config.registration_covariance = RegistrationCovarianceModel::kClustered;
    const auto clustered =
        RegistrationCovariance(Eigen::Isometry3d::Identity(), matches, nullptr, config);
    ASSERT_TRUE(independent.valid && clustered.valid);
    EXPECT_EQ(clustered.clusters, 40);
    // Ten copies: the honest covariance is ~10x the independent one (within the sandwich's
    // sampling error over 40 clusters).
    const double ratio = clustered.covariance.trace() / independent.covariance.trace();
    EXPECT_GT(ratio, 5.0);
    EXPECT_LT(ratio, 20.0);
}

// The clusters are the map cells (registration_cluster_m) the residuals fall in: 8 surface patches,
// each 30 map points within one 4 m cell sharing the patch's error. With 4 m cells the model
// counts 8 clusters and is many times the independent model; with 1 cm cells (every residual its
// own cluster) the same residuals look independent and the model stays near the independent one.
TEST(PoseInformation, ClustersAreTheMapCellsOfTheResiduals) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> within(-0.5, 0.5);
    std::normal_distribution<double> shared_error(0.0, 0.3), own_error(0.0, 0.03);
    std::vector<Correspondence> matches;
    for (int patch = 0; patch < 8; ++patch) {
        // Cell centres 8 m apart around the sensor, on both sides and at two heights.
        const Eigen::Vector3d centre(8.0 * (patch % 4) - 10.0, patch < 4 ? 10.0 : -14.0,
                                     patch % 2 == 0 ? 2.0 : -2.0);
        const Eigen::Vector3d shared(shared_error(rng), shared_error(rng), shared_error(rng));
        for (int i = 0; i < 30; ++i) {
            const Eigen::Vector3d q =
                centre + Eigen::Vector3d(within(rng), within(rng), within(rng));
            const Eigen::Vector3d own(own_error(rng), own_error(rng), own_error(rng));
            matches.push_back({q + shared + own, q, Eigen::Matrix3d::Identity() / 0.3});
        }
    }
    MapperConfig config;
    config.registration_floor_sigma_translation_m = 0.0;
    config.registration_floor_sigma_rotation_rad = 0.0;
    config.registration_covariance = RegistrationCovarianceModel::kIndependent;
    const auto independent =
        RegistrationCovariance(Eigen::Isometry3d::Identity(), matches, nullptr, config);
    config.registration_covariance = RegistrationCovarianceModel::kClustered;
    config.registration_cluster_m = 4.0;
    const auto cells =
        RegistrationCovariance(Eigen::Isometry3d::Identity(), matches, nullptr, config);
    config.registration_cluster_m = 0.01;
    const auto points =
        RegistrationCovariance(Eigen::Isometry3d::Identity(), matches, nullptr, config);
    ASSERT_TRUE(independent.valid && cells.valid && points.valid);
    EXPECT_EQ(cells.clusters, 8);
    EXPECT_EQ(points.clusters, 240);
    const double cells_ratio = cells.covariance.trace() / independent.covariance.trace();
    const double points_ratio = points.covariance.trace() / independent.covariance.trace();
    std::printf("clustered / independent trace: 4 m cells %.2f, 1 cm cells %.2f\n", cells_ratio,
                points_ratio);
    EXPECT_GT(cells_ratio, 5.0);
    EXPECT_LT(points_ratio, 2.0);
    EXPECT_GT(cells_ratio, 4.0 * points_ratio);
}

TEST(PoseInformation, FloorIsAddedAndTooFewMatchesAreInvalid) {
    MapperConfig config;
    config.registration_covariance = RegistrationCovarianceModel::kIndependent;
    std::mt19937 rng(3);
    std::vector<Correspondence> matches;
    for (const auto &p : Points(100, rng)) matches.push_back({p, p, Eigen::Matrix3d::Identity()});
    const auto with_floor =
        RegistrationCovariance(Eigen::Isometry3d::Identity(), matches, nullptr, config);
    config.registration_floor_sigma_translation_m = 0.0;
    config.registration_floor_sigma_rotation_rad = 0.0;
    const auto without =
        RegistrationCovariance(Eigen::Isometry3d::Identity(), matches, nullptr, config);
    const MapperConfig defaults;
    EXPECT_NEAR(with_floor.covariance(0, 0) - without.covariance(0, 0),
                std::pow(defaults.registration_floor_sigma_translation_m, 2), 1e-12);
    EXPECT_NEAR(with_floor.covariance(5, 5) - without.covariance(5, 5),
                std::pow(defaults.registration_floor_sigma_rotation_rad, 2), 1e-12);
    matches.resize(2);
    EXPECT_FALSE(
        RegistrationCovariance(Eigen::Isometry3d::Identity(), matches, nullptr, config).valid);
}

// Degeneracy (Zhang et al. 2016): matches on surfaces whose normals are z (ground) and y (a wall
// along x) say nothing about x (along the track). With registration_weak_ratio the x direction of
// the translation block is weak: the information along x is zero, across it it is unchanged;
// without the ratio nothing is weak.
TEST(PoseInformation, WeakDirectionGetsNoInformation) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-20.0, 20.0);
    std::vector<Correspondence> matches;
    for (int i = 0; i < 300; ++i) {
        const bool wall = i % 3 == 0;
        const Eigen::Vector3d p(u(rng), wall ? 8.0 : u(rng), wall ? 0.1 * u(rng) : 0.0);
        Eigen::Matrix3d W = Eigen::Matrix3d::Zero();  // point-to-plane: only the normal is measured
        W(wall ? 1 : 2, wall ? 1 : 2) = 1.0 / 0.1;
        W += 1e-3 * Eigen::Matrix3d::Identity();  // a thick plane
        matches.push_back({p, p, W});
    }
    MapperConfig config;
    config.registration_covariance = RegistrationCovarianceModel::kIndependent;
    const RegisteredPose plain =
        RegistrationCovariance(Eigen::Isometry3d::Identity(), matches, nullptr, config);
    ASSERT_TRUE(plain.valid);
    EXPECT_EQ(plain.weak_directions, 0);
    config.registration_weak_ratio = 0.01;
    const RegisteredPose weak =
        RegistrationCovariance(Eigen::Isometry3d::Identity(), matches, nullptr, config);
    ASSERT_TRUE(weak.valid);
    EXPECT_EQ(weak.weak_directions, 1);
    const Vector6d x = Vector6d::Unit(0), y = Vector6d::Unit(1), z = Vector6d::Unit(2);
    EXPECT_LT(weak.information.col(0).norm(), 1e-9 * weak.information.norm());
    EXPECT_GT(weak.covariance(0, 0), 1e6);  // no information: the prior carries x
    EXPECT_NEAR(y.dot(weak.information * y), y.dot(plain.information * y),
                1e-6 * y.dot(plain.information * y));
    EXPECT_NEAR(z.dot(weak.information * z), z.dot(plain.information * z),
                1e-6 * z.dot(plain.information * z));
    EXPECT_LT((weak.strong_projector * x).norm(), 1e-9);
}

}  // namespace
}  // namespace dorado::mapping
