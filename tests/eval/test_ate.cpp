#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "dorado/eval/absolute_trajectory_error.hpp"

namespace dorado::eval {
namespace {

// A 3D reference path (not degenerate: it spans all three axes) and an estimate in another frame.
AssociatedPoses Transformed(const Eigen::Isometry3d &T_est_ref, double scale, double noise_m) {
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, noise_m);
    AssociatedPoses poses;
    for (int k = 0; k < 100; ++k) {
        const double t = 0.1 * k;
        Eigen::Isometry3d T_ref = Eigen::Isometry3d::Identity();
        T_ref.translation() = Eigen::Vector3d(5 * std::cos(t), 3 * std::sin(t), 0.5 * t);
        Eigen::Isometry3d T_est = Eigen::Isometry3d::Identity();
        T_est.translation() = scale * (T_est_ref * T_ref.translation()) +
                              Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
        poses.stamps_ns.push_back(k);
        poses.T_world_ref.push_back(T_ref);
        poses.T_world_est.push_back(T_est);
    }
    return poses;
}

Eigen::Isometry3d SomeTransform() {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, -1, 2).normalized()).matrix();
    T.translation() = Eigen::Vector3d(10, -4, 2);
    return T;
}

TEST(Ate, Se3AlignmentUndoesARigidTransform) {
    const AteResult ate = ComputeAte(Transformed(SomeTransform(), 1.0, 0.0));
    EXPECT_NEAR(ate.scale, 1.0, 1e-12);
    EXPECT_TRUE(ate.T_ref_est.isApprox(SomeTransform().inverse(), 1e-9));
    for (const double e : ate.translation_m) EXPECT_LT(e, 1e-9);
}

TEST(Ate, Sim3AlignmentRecoversScaleThatSe3Cannot) {
    const AssociatedPoses poses = Transformed(SomeTransform(), 2.0, 0.0);
    const AteResult sim3 = ComputeAte(poses, {true});
    EXPECT_NEAR(sim3.scale, 0.5, 1e-9);
    for (const double e : sim3.translation_m) EXPECT_LT(e, 1e-9);
    const AteResult se3 = ComputeAte(poses, {false});
    double max_error = 0;
    for (const double e : se3.translation_m) max_error = std::max(max_error, e);
    EXPECT_GT(max_error, 1.0);  // a doubled 10 m path cannot be matched rigidly
}

TEST(Ate, IsotropicNoiseGivesRmseNearItsSigma) {
    // Position noise of sigma per axis: the error norm has rms sigma*sqrt(3), minus the few
    // degrees of freedom the alignment absorbs (6 of 300).
    const AteResult ate = ComputeAte(Transformed(SomeTransform(), 1.0, 0.01));
    double sum_sq = 0;
    for (const double e : ate.translation_m) sum_sq += e * e;
    const double rmse = std::sqrt(sum_sq / static_cast<double>(ate.translation_m.size()));
    EXPECT_NEAR(rmse, 0.01 * std::sqrt(3.0), 0.003);
}

TEST(Ate, TooFewPosesIsAnError) {
    AssociatedPoses poses = Transformed(SomeTransform(), 1.0, 0.0);
    poses.stamps_ns.resize(2);
    poses.T_world_ref.resize(2);
    poses.T_world_est.resize(2);
    EXPECT_THROW((void)ComputeAte(poses), std::invalid_argument);
}

}  // namespace
}  // namespace dorado::eval
