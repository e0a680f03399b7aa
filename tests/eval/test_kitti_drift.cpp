// KITTI drift against hand-computed cases: a path 2 % too long, a constant heading error rate.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "dorado/core/angles.hpp"
#include "dorado/eval/kitti_drift.hpp"

namespace dorado::eval {
namespace {

Eigen::Isometry3d Pose(double x, double y, double yaw) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() << x, y, 0.0;
    T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return T;
}

// The reference drives 1000 m straight along x in 1 m steps.
AssociatedPoses Straight(const std::function<Eigen::Isometry3d(double)> &estimate) {
    AssociatedPoses poses;
    for (int k = 0; k <= 1000; ++k) {
        poses.stamps_ns.push_back(k * 100'000'000LL);
        poses.T_world_ref.push_back(Pose(k, 0.0, 0.0));
        poses.T_world_est.push_back(estimate(k));
    }
    return poses;
}

TEST(KittiDrift, ScaleErrorIsTheTranslationDrift) {
    // Every segment (L + 1 m of path: the first pose more than L further) ends 2 % of its
    // path too far: 2 (L + 1) / L % for each, no rotation.
    const DriftResult drift =
        ComputeKittiDrift(Straight([](double s) { return Pose(1.02 * s, 0.0, 0.0); }));
    const int starts[] = {90, 80, 70, 60, 50, 40, 30, 20};
    double sum = 0.0;
    for (int k = 0; k < 8; ++k)
        sum += starts[k] * 2.0 * (100.0 * (k + 1) + 1.0) / (100.0 * (k + 1));
    EXPECT_NEAR(drift.translation_percent, sum / 440.0, 1e-9);
    EXPECT_NEAR(drift.rotation_deg_per_100m, 0.0, 1e-9);
    // Segments: starts 0, 10, ..., 1000; length L fits when start + L < 1000 (strictly more
    // than L further, 1 m steps): sum over L of ceil((1000 - L) / 10) starts = 90+80+...+20.
    EXPECT_EQ(drift.segments, 90 + 80 + 70 + 60 + 50 + 40 + 30 + 20);
}

TEST(KittiDrift, ConstantCurvatureIsTheRotationDrift) {
    // The estimate turns 1 deg per 100 m while the reference goes straight: every segment of
    // length L (L + 1 m of path, the first pose beyond L) errs by (L + 1) * kappa in heading.
    const double kappa = DegToRad(1.0) / 100.0;  // rad per m
    const DriftResult drift = ComputeKittiDrift(Straight([&](double s) {
        return Pose(std::sin(kappa * s) / kappa, (1.0 - std::cos(kappa * s)) / kappa, kappa * s);
    }));
    // Hand-computed: mean over segments of (L + 1) / L deg per 100 m, weights = starts per L.
    double sum = 0.0, count = 0.0, sum_t = 0.0;
    const int starts[] = {90, 80, 70, 60, 50, 40, 30, 20};
    for (int k = 0; k < 8; ++k) {
        const double L = 100.0 * (k + 1), s = L + 1.0;
        sum += starts[k] * s / L;
        // Translation: |(s, 0) - (sin(kappa s), 1 - cos(kappa s)) / kappa| / L.
        const double dx = s - std::sin(kappa * s) / kappa, dy = (1.0 - std::cos(kappa * s)) / kappa;
        sum_t += starts[k] * std::hypot(dx, dy) / L;
        count += starts[k];
    }
    EXPECT_NEAR(drift.rotation_deg_per_100m, sum / count, 1e-6);
    EXPECT_NEAR(drift.translation_percent, 100.0 * sum_t / count, 1e-6);
    EXPECT_NEAR(drift.rotation_deg_per_100m, 1.0, 0.01);
}

TEST(KittiDrift, ShortPathHasNoSegment) {
    AssociatedPoses poses;
    for (int k = 0; k <= 50; ++k) {
        poses.stamps_ns.push_back(k);
        poses.T_world_ref.push_back(Pose(k, 0, 0));
        poses.T_world_est.push_back(Pose(k, 0, 0));
    }
    EXPECT_EQ(ComputeKittiDrift(poses).segments, 0);
    EXPECT_THROW((void)ComputeKittiDrift(poses, {{}, 10}), std::invalid_argument);
}

}  // namespace
}  // namespace dorado::eval
