#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "dorado/core/trajectory.hpp"
#include "dorado/eval/association.hpp"

namespace dorado::eval {
namespace {

constexpr int64_t kMs = 1'000'000;

Eigen::Isometry3d Translation(double x, double y, double z) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(x, y, z);
    return T;
}

// Reference moving along x at 2 m/s, one pose every 100 ms from t = 0 to 1 s.
Trajectory StraightReference() {
    Trajectory reference;
    for (int k = 0; k <= 10; ++k) reference.Append(k * 100 * kMs, Translation(0.2 * k, 0, 0));
    return reference;
}

TEST(AssociateInterpolated, ReferenceIsInterpolatedAtEstimatedStamps) {
    Trajectory estimate;
    estimate.Append(-50 * kMs, Translation(0, 0, 0));   // before the reference: unmatched
    estimate.Append(125 * kMs, Translation(9, 9, 9));   // between 100 and 200 ms
    estimate.Append(700 * kMs, Translation(1, 1, 1));   // exactly on a reference pose
    estimate.Append(1001 * kMs, Translation(0, 0, 0));  // after the reference: unmatched
    const AssociatedPoses a = Associate(StraightReference(), estimate);
    ASSERT_EQ(a.size(), 2u);
    EXPECT_EQ(a.stamps_ns[0], 125 * kMs);
    // 2 m/s * 0.125 s.
    EXPECT_NEAR((a.T_world_ref[0].translation() - Eigen::Vector3d(0.25, 0, 0)).norm(), 0, 1e-12);
    EXPECT_NEAR((a.T_world_est[0].translation() - Eigen::Vector3d(9, 9, 9)).norm(), 0, 1e-12);
    EXPECT_NEAR(a.T_world_ref[1].translation().x(), 1.4, 1e-12);
    ASSERT_EQ(a.unmatched_est_stamps_ns.size(), 2u);
    EXPECT_EQ(a.unmatched_est_stamps_ns[0], -50 * kMs);
    EXPECT_EQ(a.unmatched_est_stamps_ns[1], 1001 * kMs);
}

TEST(AssociateInterpolated, GapLongerThanMaxGapIsNotBridged) {
    Trajectory reference;
    reference.Append(0, Translation(0, 0, 0));
    reference.Append(100 * kMs, Translation(1, 0, 0));
    reference.Append(900 * kMs, Translation(2, 0, 0));  // an 800 ms hole in the ground truth
    Trajectory estimate;
    estimate.Append(50 * kMs, Eigen::Isometry3d::Identity());
    estimate.Append(500 * kMs, Eigen::Isometry3d::Identity());
    AssociationConfig config;
    config.max_gap_ns = 200 * kMs;
    const AssociatedPoses a = Associate(reference, estimate, config);
    ASSERT_EQ(a.size(), 1u);
    EXPECT_EQ(a.stamps_ns[0], 50 * kMs);
    ASSERT_EQ(a.unmatched_est_stamps_ns.size(), 1u);
    EXPECT_EQ(a.unmatched_est_stamps_ns[0], 500 * kMs);
}

TEST(AssociateNearest, MatchesEvoNearestStampWithinMaxDiff) {
    // Estimate shorter than reference: each estimated pose takes the nearest reference pose.
    Trajectory estimate;
    estimate.Append(104 * kMs, Translation(5, 0, 0));  // nearest 100 ms, 4 ms away
    estimate.Append(150 * kMs, Translation(6, 0, 0));  // tie 100/200 -> the earlier; 50 ms > 10 ms
    estimate.Append(297 * kMs, Translation(7, 0, 0));  // nearest 300 ms, 3 ms away
    AssociationConfig config;
    config.method = AssociationMethod::kNearest;
    const AssociatedPoses a = Associate(StraightReference(), estimate, config);
    ASSERT_EQ(a.size(), 2u);
    EXPECT_EQ(a.stamps_ns[0], 104 * kMs);
    EXPECT_NEAR(a.T_world_ref[0].translation().x(), 0.2, 1e-12);  // not interpolated
    EXPECT_NEAR(a.T_world_ref[1].translation().x(), 0.6, 1e-12);
    EXPECT_NEAR(a.T_world_est[1].translation().x(), 7.0, 1e-12);
    ASSERT_EQ(a.unmatched_est_stamps_ns.size(), 1u);
    EXPECT_EQ(a.unmatched_est_stamps_ns[0], 150 * kMs);

    config.max_time_diff_ns = 50 * kMs;  // now the tie is accepted, with the earlier pose
    const AssociatedPoses wide = Associate(StraightReference(), estimate, config);
    ASSERT_EQ(wide.size(), 3u);
    EXPECT_NEAR(wide.T_world_ref[1].translation().x(), 0.2, 1e-12);
}

TEST(AssociateNearest, LongerEstimateIsMatchedFromTheReferenceSide) {
    // Estimate at 40 Hz, reference at 10 Hz: evo iterates over the shorter (reference).
    Trajectory estimate;
    for (int k = 0; k <= 40; ++k) estimate.Append(k * 25 * kMs + 2 * kMs, Translation(k, 0, 0));
    AssociationConfig config;
    config.method = AssociationMethod::kNearest;
    const AssociatedPoses a = Associate(StraightReference(), estimate, config);
    ASSERT_EQ(a.size(), 11u);
    for (std::size_t k = 0; k < a.size(); ++k) {
        EXPECT_EQ(a.stamps_ns[k], static_cast<int64_t>(k) * 100 * kMs + 2 * kMs);
        EXPECT_NEAR(a.T_world_est[k].translation().x(), 4.0 * static_cast<double>(k), 1e-12);
    }
    EXPECT_EQ(a.unmatched_est_stamps_ns.size(), 30u);
}

TEST(KeepStamps, KeepsOnlyListedStamps) {
    Trajectory estimate;
    for (int k = 0; k <= 10; ++k) estimate.Append(k * 100 * kMs, Translation(k, 0, 0));
    const AssociatedPoses a = Associate(StraightReference(), estimate);
    const AssociatedPoses kept = KeepStamps(a, {200 * kMs, 500 * kMs, 777 * kMs});
    ASSERT_EQ(kept.size(), 2u);
    EXPECT_EQ(kept.stamps_ns[1], 500 * kMs);
    EXPECT_NEAR(kept.T_world_est[1].translation().x(), 5.0, 1e-12);
}

}  // namespace
}  // namespace dorado::eval
