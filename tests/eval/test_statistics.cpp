#include <gtest/gtest.h>

#include <cmath>

#include "dorado/eval/statistics.hpp"

namespace dorado::eval {
namespace {

TEST(Statistics, MatchesHandComputedValuesForEvenCount) {
    // {4, 1, 3, 2}: mean 2.5, median (2+3)/2, mean of squares 30/4, population variance 1.25.
    const Statistics s = ComputeStatistics({4.0, 1.0, 3.0, 2.0});
    EXPECT_EQ(s.count, 4u);
    EXPECT_DOUBLE_EQ(s.mean, 2.5);
    EXPECT_DOUBLE_EQ(s.median, 2.5);
    EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(7.5));
    EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));
    EXPECT_DOUBLE_EQ(s.min, 1.0);
    EXPECT_DOUBLE_EQ(s.max, 4.0);
}

TEST(Statistics, MedianOfOddCountIsTheMiddleValue) {
    const Statistics s = ComputeStatistics({10.0, -1.0, 7.0});
    EXPECT_DOUBLE_EQ(s.median, 7.0);
    EXPECT_DOUBLE_EQ(
        s.std, std::sqrt(((10 - 16.0 / 3) * (10 - 16.0 / 3) + (-1 - 16.0 / 3) * (-1 - 16.0 / 3) +
                          (7 - 16.0 / 3) * (7 - 16.0 / 3)) /
                         3.0));
}

TEST(Statistics, SmallSpreadAroundLargeMeanKeepsItsStd) {
    // A one-pass formula would lose the 1e-6 spread against a mean of 1e4.
    const Statistics s = ComputeStatistics({1e4 - 1e-6, 1e4 + 1e-6});
    EXPECT_NEAR(s.std, 1e-6, 1e-12);
}

TEST(Statistics, EmptySeriesIsNanWithZeroCount) {
    const Statistics s = ComputeStatistics({});
    EXPECT_EQ(s.count, 0u);
    EXPECT_TRUE(std::isnan(s.rmse));
    EXPECT_TRUE(std::isnan(s.median));
}

}  // namespace
}  // namespace dorado::eval
