// RPE checked against answers computed here without the library's code path:
// - a closed form: reference in straight-line motion, estimate on a circular arc;
// - brute force with general 4x4 matrix inverses on a random 3D trajectory.
// Both are the quantities of `evo_rpe tum GT EST --delta 1 --delta_unit f` (translation_part, and
// angle_deg) on the same pairs: E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j), consecutive pairs (i, i + 1).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

#include "dorado/core/angles.hpp"
#include "dorado/core/trajectory.hpp"
#include "dorado/eval/relative_pose_error.hpp"

namespace dorado::eval {
namespace {

Eigen::Isometry3d Pose(const Eigen::Matrix3d &R, const Eigen::Vector3d &t) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = R;
    T.translation() = t;
    return T;
}

Eigen::Matrix3d Rz(double a) {
    return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).matrix();
}

// Poses at the same stamps in both trajectories, so the association is exact.
AssociatedPoses SameStamps(const std::vector<int64_t> &stamps,
                           const std::vector<Eigen::Isometry3d> &ref,
                           const std::vector<Eigen::Isometry3d> &est) {
    Trajectory reference, estimate;
    for (std::size_t k = 0; k < stamps.size(); ++k) {
        reference.Append(stamps[k], ref[k]);
        estimate.Append(stamps[k], est[k]);
    }
    return Associate(reference, estimate);
}

TEST(Rpe, PerFrameEqualsClosedFormOfLineAgainstArc) {
    // Reference: straight line along x at vq. Estimate: forward speed v with yaw rate w (an arc).
    // Both start from arbitrary (different) world poses, which the RPE must not see.
    // Over dt: Q_ij = translation (vq dt, 0, 0); P_ij = [Rz(w dt), (v/w sin(w dt), v/w (1 - cos(w
    // dt)), 0)] so E = [Rz(w dt), P_ij.t - (vq dt, 0, 0)], |t(E)| and angle(E) = |w dt| follow by
    // hand.
    const double vq = 1.3, v = 1.5, w = 0.4;
    const Eigen::Isometry3d T0_ref =
        Pose(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).matrix(), {4, -2, 1});
    const Eigen::Isometry3d T0_est =
        Pose(Eigen::AngleAxisd(-1.1, Eigen::Vector3d(0, 1, 1).normalized()).matrix(), {-3, 5, 2});
    std::vector<int64_t> stamps;
    std::vector<Eigen::Isometry3d> ref, est;
    for (int k = 0; k < 60; ++k) {
        // Irregular stamps, as a radar's are.
        const double t = 0.1 * k + 0.02 * std::sin(1.7 * k);
        stamps.push_back(static_cast<int64_t>(std::llround(t * 1e9)));
        const double ts = static_cast<double>(stamps.back()) * 1e-9;
        ref.push_back(T0_ref * Pose(Eigen::Matrix3d::Identity(), {vq * ts, 0, 0}));
        est.push_back(T0_est * Pose(Rz(w * ts),
                                    {v / w * std::sin(w * ts), v / w * (1 - std::cos(w * ts)), 0}));
    }
    const RelativeErrors rpe = ComputeRpe(SameStamps(stamps, ref, est), PairSelection{});
    ASSERT_EQ(rpe.pairs.size(), stamps.size() - 1);
    for (std::size_t k = 0; k < rpe.pairs.size(); ++k) {
        ASSERT_EQ(rpe.pairs[k].i, k);
        ASSERT_EQ(rpe.pairs[k].j, k + 1);
        const double dt = static_cast<double>(stamps[k + 1] - stamps[k]) * 1e-9;
        const double ex = v / w * std::sin(w * dt) - vq * dt;
        const double ey = v / w * (1 - std::cos(w * dt));
        EXPECT_NEAR(rpe.translation_m[k], std::hypot(ex, ey), 1e-9) << "pair " << k;
        EXPECT_NEAR(rpe.rotation_deg[k], RadToDeg(w * dt), 1e-7) << "pair " << k;
    }
}

TEST(Rpe, PerFrameEqualsBruteForceWithGeneralMatrixInverse) {
    std::mt19937 rng(42);
    std::normal_distribution<double> noise(0.0, 1.0);
    const auto random_rotation = [&](double sigma) {
        const Eigen::Vector3d axis(noise(rng), noise(rng), noise(rng));
        return Eigen::AngleAxisd(sigma * axis.norm(), axis.normalized()).matrix();
    };
    std::vector<int64_t> stamps;
    std::vector<Eigen::Isometry3d> ref, est;
    Eigen::Isometry3d Q = Eigen::Isometry3d::Identity();
    for (int k = 0; k < 200; ++k) {
        stamps.push_back(int64_t{1'600'000'000'000'000'000} + k * 100'000'000LL);
        Q = Q * Pose(random_rotation(0.1),
                     {1.0 + 0.1 * noise(rng), 0.1 * noise(rng), 0.05 * noise(rng)});
        ref.push_back(Q);
        // The estimate: the reference with a wandering error in every pose.
        est.push_back(Q * Pose(random_rotation(0.03),
                               {0.05 * noise(rng), 0.05 * noise(rng), 0.05 * noise(rng)}));
    }
    const RelativeErrors rpe = ComputeRpe(SameStamps(stamps, ref, est), PairSelection{});
    ASSERT_EQ(rpe.pairs.size(), 199u);
    for (std::size_t k = 0; k < rpe.pairs.size(); ++k) {
        const Eigen::Matrix4d Qi = ref[k].matrix(), Qj = ref[k + 1].matrix();
        const Eigen::Matrix4d Pi = est[k].matrix(), Pj = est[k + 1].matrix();
        // General (LU) 4x4 inverses, not the isometry shortcut the library uses.
        const Eigen::Matrix4d E = (Qi.inverse() * Qj).inverse() * (Pi.inverse() * Pj);
        const double cos_angle = (E.topLeftCorner<3, 3>().trace() - 1) / 2;
        const double angle = std::acos(std::clamp(cos_angle, -1.0, 1.0));
        const double translation = E.topRightCorner<3, 1>().norm();
        EXPECT_NEAR(rpe.translation_m[k], translation, 1e-9);
        EXPECT_NEAR(rpe.rotation_deg[k], RadToDeg(angle), 1e-6);
    }
}

TEST(Rpe, RotationErrorIsSplitOverTheBodyAxes) {
    // A straight reference and an estimate that wobbles about one body axis only: the error of a
    // pair is that axis' angle change, all of it on that axis.
    for (int axis = 0; axis < 3; ++axis) {
        std::vector<int64_t> stamps;
        std::vector<Eigen::Isometry3d> ref, est;
        std::vector<double> angle;
        for (int k = 0; k < 20; ++k) {
            stamps.push_back(k * 100'000'000LL);
            angle.push_back(0.02 * std::sin(0.9 * k));
            ref.push_back(Pose(Eigen::Matrix3d::Identity(), {0.1 * k, 0, 0}));
            est.push_back(
                ref.back() *
                Pose(Eigen::AngleAxisd(angle.back(), Eigen::Vector3d::Unit(axis)).matrix(),
                     {0, 0, 0}));
        }
        const RelativeErrors rpe = ComputeRpe(SameStamps(stamps, ref, est), PairSelection{});
        ASSERT_EQ(rpe.pairs.size(), 19u);
        for (std::size_t k = 0; k < rpe.pairs.size(); ++k) {
            const double expected = RadToDeg(std::abs(angle[k + 1] - angle[k]));
            const double by_axis[3] = {rpe.roll_deg[k], rpe.pitch_deg[k], rpe.yaw_deg[k]};
            for (int a = 0; a < 3; ++a)
                EXPECT_NEAR(by_axis[a], a == axis ? expected : 0.0, 1e-9) << axis << " " << k;
            EXPECT_NEAR(rpe.rotation_deg[k], expected, 1e-9);
        }
    }
}

TEST(Rpe, IdenticalTrajectoriesHaveZeroErrorEvenForTinyMotion) {
    std::vector<int64_t> stamps;
    std::vector<Eigen::Isometry3d> ref;
    for (int k = 0; k < 10; ++k) {
        stamps.push_back(k * 1'000'000LL);
        ref.push_back(Pose(Rz(1e-9 * k), {1e-6 * k, 0, 0}));
    }
    const RelativeErrors rpe = ComputeRpe(SameStamps(stamps, ref, ref), PairSelection{});
    for (std::size_t k = 0; k < rpe.pairs.size(); ++k) {
        EXPECT_LT(rpe.translation_m[k], 1e-15);
        EXPECT_LT(rpe.rotation_deg[k], 1e-12);
    }
}

TEST(SelectPairs, FramesAreEvoConsecutivePairs) {
    AssociatedPoses poses;
    for (int k = 0; k < 10; ++k) {
        poses.stamps_ns.push_back(k);
        poses.T_world_ref.push_back(Eigen::Isometry3d::Identity());
        poses.T_world_est.push_back(Eigen::Isometry3d::Identity());
    }
    // evo: ids = arange(0, 10, 3) = 0 3 6 9 -> (0,3) (3,6) (6,9).
    const auto pairs = SelectPairs(poses, {3.0, DeltaUnit::kFrames, 0.1});
    ASSERT_EQ(pairs.size(), 3u);
    EXPECT_EQ(pairs[2].i, 6u);
    EXPECT_EQ(pairs[2].j, 9u);
    EXPECT_THROW((void)SelectPairs(poses, {1.5, DeltaUnit::kFrames, 0.1}), std::invalid_argument);
    EXPECT_THROW((void)SelectPairs(poses, {0.0, DeltaUnit::kFrames, 0.1}), std::invalid_argument);
}

TEST(SelectPairs, SecondsFollowTheStampsAndSkipGaps) {
    // 10 Hz from 0 to 2.0 s, then nothing until 3.55 s, then 10 Hz again to 5.05 s.
    AssociatedPoses poses;
    const auto add = [&](int64_t ms) {
        poses.stamps_ns.push_back(ms * 1'000'000);
        poses.T_world_ref.push_back(Eigen::Isometry3d::Identity());
        poses.T_world_est.push_back(Eigen::Isometry3d::Identity());
    };
    for (int64_t ms = 0; ms <= 2000; ms += 100) add(ms);
    for (int64_t ms = 3550; ms <= 5050; ms += 100) add(ms);
    const auto pairs = SelectPairs(poses, {1.0, DeltaUnit::kSeconds, 0.1});
    // 0->1 s, 1->2 s; from 2.0 s the nearest to 3.0 s is 3.55 s (out of tolerance), and so on
    // until 2.55 s would be needed; the next pair starts at 3.55 s: 3.55->4.55 s.
    ASSERT_EQ(pairs.size(), 3u);
    EXPECT_EQ(poses.stamps_ns[pairs[0].j], 1'000'000'000);
    EXPECT_EQ(poses.stamps_ns[pairs[1].i], 1'000'000'000);
    EXPECT_EQ(poses.stamps_ns[pairs[1].j], 2'000'000'000);
    EXPECT_EQ(poses.stamps_ns[pairs[2].i], 3'550'000'000);
    EXPECT_EQ(poses.stamps_ns[pairs[2].j], 4'550'000'000);
}

TEST(SelectPairs, MetersFollowTheReferencePath) {
    // Reference moves 0.5 m per pose; the estimate stands still (its path must not matter).
    AssociatedPoses poses;
    for (int k = 0; k < 8; ++k) {
        poses.stamps_ns.push_back(k);
        poses.T_world_ref.push_back(Pose(Eigen::Matrix3d::Identity(), {0.5 * k, 0, 0}));
        poses.T_world_est.push_back(Eigen::Isometry3d::Identity());
    }
    const auto pairs = SelectPairs(poses, {1.2, DeltaUnit::kMeters, 0.1});
    ASSERT_EQ(pairs.size(), 2u);  // (0,3) and (3,6): 1.5 m each
    EXPECT_EQ(pairs[0].j, 3u);
    EXPECT_EQ(pairs[1].i, 3u);
    EXPECT_EQ(pairs[1].j, 6u);
    // Translation error of a still estimate over 1.5 m of reference motion is 1.5 m.
    const RelativeErrors rpe = ComputeRpe(poses, pairs);
    EXPECT_NEAR(rpe.translation_m[0], 1.5, 1e-12);
}

TEST(DeltaUnit, ParsesNamesAndRejectsOthers) {
    EXPECT_EQ(ParseDeltaUnit("f"), DeltaUnit::kFrames);
    EXPECT_EQ(ParseDeltaUnit("seconds"), DeltaUnit::kSeconds);
    EXPECT_EQ(ParseDeltaUnit("m"), DeltaUnit::kMeters);
    EXPECT_THROW((void)ParseDeltaUnit("degrees"), std::invalid_argument);
}

}  // namespace
}  // namespace dorado::eval
