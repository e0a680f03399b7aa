// The gyro bias from stationary intervals, against the bias the samples were made with.
#include <gtest/gtest.h>

#include <random>

#include "dorado/core/gyro_bias.hpp"

namespace dorado {
namespace {

// 200 Hz samples of a gyro with a constant bias and white noise, plus a true rate.
std::vector<ImuSample> Interval(const Eigen::Vector3d &bias, const Eigen::Vector3d &rate,
                                double sigma, int count, std::mt19937_64 &rng) {
    std::normal_distribution<double> n(0.0, sigma);
    std::vector<ImuSample> samples(static_cast<std::size_t>(count));
    for (auto &s : samples)
        s.omega_imu_radps = bias + rate + Eigen::Vector3d(n(rng), n(rng), n(rng));
    return samples;
}

TEST(GyroBias, MeanOfTheSamplesAtRest) {
    std::mt19937_64 rng(3);
    const Eigen::Vector3d bias(2e-3, -1.5e-3, 0.8e-3);
    const double sigma = 2.4e-3;  // 1.7e-4 rad/s/sqrt(Hz) at 200 Hz
    GyroBiasEstimator estimator;
    // First interval after a moving scan: not at rest over the whole interval, ignored.
    estimator.AddInterval(false, Interval(bias, Eigen::Vector3d(0, 0, 0.3), sigma, 13, rng));
    estimator.AddInterval(true, Interval(bias, Eigen::Vector3d(0, 0, 0.1), sigma, 13, rng));
    EXPECT_EQ(estimator.count(), 0);
    EXPECT_FALSE(estimator.has_bias());
    EXPECT_EQ(estimator.bias_imu_radps(), Eigen::Vector3d::Zero());
    for (int k = 0; k < 30; ++k)  // 2 s at rest
        estimator.AddInterval(true, Interval(bias, Eigen::Vector3d::Zero(), sigma, 13, rng));
    ASSERT_TRUE(estimator.has_bias());
    EXPECT_EQ(estimator.count(), 390);
    // The mean of 390 samples: 4 sigma / sqrt(390) = 4.9e-4 rad/s.
    EXPECT_LT((estimator.bias_imu_radps() - bias).cwiseAbs().maxCoeff(),
              4.0 * sigma / std::sqrt(390.0));
    // Moving again: the bias stays.
    const Eigen::Vector3d before = estimator.bias_imu_radps();
    estimator.AddInterval(false, Interval(bias, Eigen::Vector3d(0.2, 0, 0), sigma, 13, rng));
    EXPECT_EQ(estimator.bias_imu_radps(), before);
    // Corrected subtracts it.
    std::vector<ImuSample> one(1);
    one[0].omega_imu_radps = Eigen::Vector3d(0.1, 0.2, 0.3);
    EXPECT_TRUE(estimator.Corrected(one)[0].omega_imu_radps.isApprox(
        Eigen::Vector3d(0.1, 0.2, 0.3) - before));
}

// A bias that moved between two stops is followed by the exponential window.
TEST(GyroBias, FollowsADriftedBiasAtTheNextStop) {
    std::mt19937_64 rng(4);
    GyroBiasEstimator estimator(50, 400);
    const Eigen::Vector3d b0(1e-3, 0, 0), b1(3e-3, 0, 0);
    for (int k = 0; k < 40; ++k)
        estimator.AddInterval(true, Interval(b0, Eigen::Vector3d::Zero(), 1e-3, 13, rng));
    EXPECT_NEAR(estimator.bias_imu_radps().x(), 1e-3, 3e-4);
    estimator.AddInterval(false, {});
    for (int k = 0; k < 200; ++k)
        estimator.AddInterval(true, Interval(b1, Eigen::Vector3d::Zero(), 1e-3, 13, rng));
    // 2600 samples at the new bias with a 400-sample window: (1 - 1/400)^2600 = 0.15 % left.
    EXPECT_NEAR(estimator.bias_imu_radps().x(), 3e-3, 3e-4);
}

TEST(GyroBias, RejectsABadWindow) {
    EXPECT_THROW(GyroBiasEstimator(0, 10), std::invalid_argument);
    EXPECT_THROW(GyroBiasEstimator(100, 10), std::invalid_argument);
}

}  // namespace
}  // namespace dorado
