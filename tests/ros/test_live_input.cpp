// The live node's stream bookkeeping (ros/common/live_input.hpp), without ROS: which stamps are
// dropped, which gaps reset, how faults are summarised, the latency quantiles.
#include <gtest/gtest.h>

#include <cmath>

#include "live_input.hpp"

namespace {

using dorado::ros_node::FaultLog;
using dorado::ros_node::GapPolicy;
using dorado::ros_node::GapVerdict;
using dorado::ros_node::LatencyStats;
using dorado::ros_node::StampGuard;
using dorado::ros_node::StampVerdict;

constexpr int64_t kMs = 1'000'000;

TEST(StampGuard, DropsRepeatedAndOlderStampsAndResetsAfterALongGap) {
    StampGuard guard(GapPolicy{1.0, 5.0});
    EXPECT_EQ(guard.Check(100 * kMs), StampVerdict::kAccept);
    EXPECT_EQ(guard.Accept(100 * kMs), GapVerdict::kNone);
    EXPECT_EQ(guard.Accept(200 * kMs), GapVerdict::kNone);  // ordinary interval 0.1 s
    EXPECT_EQ(guard.Check(200 * kMs), StampVerdict::kDuplicate);
    EXPECT_EQ(guard.Check(150 * kMs), StampVerdict::kOutOfOrder);
    EXPECT_EQ(guard.Accept(800 * kMs), GapVerdict::kIntegrate);  // 0.6 s > 5 x 0.1 s
    EXPECT_NEAR(guard.last_interval_s(), 0.6, 1e-12);
    EXPECT_NEAR(guard.ordinary_interval_s(), 0.1, 1e-12);  // a gap does not change it
    EXPECT_EQ(guard.Accept(900 * kMs), GapVerdict::kNone);
    EXPECT_EQ(guard.Accept(2000 * kMs), GapVerdict::kReset);  // 1.1 s > max_gap_s
    // A gap the node made itself (it dropped late scans in between) is integrated, not reported.
    EXPECT_EQ(guard.Accept(3500 * kMs, true), GapVerdict::kNone);
    EXPECT_NEAR(guard.last_interval_s(), 1.5, 1e-12);
}

TEST(FaultLog, ReportsTheFirstOfACauseAndSummarisesTheRest) {
    FaultLog log;
    EXPECT_TRUE(log.Count("late", "first"));
    EXPECT_FALSE(log.Count("late", "second"));
    EXPECT_TRUE(log.Count("out of order", "x"));
    EXPECT_EQ(log.TakeRecent(), "late 2, out of order 1");
    EXPECT_EQ(log.TakeRecent(), "");
    EXPECT_FALSE(log.Count("late", "third"));
    EXPECT_EQ(log.TakeRecent(), "late 1");
    EXPECT_EQ(log.totals().at("late"), 3);
    EXPECT_EQ(log.first_details().at("late"), "first");
    EXPECT_EQ(log.total(), 4);
}

TEST(LatencyStats, NearestRankQuantiles) {
    LatencyStats stats;
    EXPECT_TRUE(std::isnan(stats.Quantile(0.5)));
    for (int i = 100; i >= 1; --i) stats.Add(i);  // 1..100 ms
    EXPECT_EQ(stats.Quantile(0.5), 50.0);
    EXPECT_EQ(stats.Quantile(0.95), 95.0);
    EXPECT_EQ(stats.Quantile(1.0), 100.0);
}

}  // namespace
