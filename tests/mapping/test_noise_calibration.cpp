// The online covariance matching (noise_calibration.hpp) recovers the scales that generated the
// innovations, stays at 1 for honest models, and one outlier moves it little.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <random>

#include "dorado/mapping/noise_calibration.hpp"

namespace dorado::mapping {
namespace {

// A random covariance: a random rotation of diag(e) with e log-uniform in [lo, hi].
Matrix6d RandomCovariance(std::mt19937 &rng, double lo, double hi) {
    std::uniform_real_distribution<double> u(std::log(lo), std::log(hi));
    std::normal_distribution<double> n;
    Matrix6d C = Matrix6d::Zero();
    for (int block = 0; block < 2; ++block) {
        Eigen::Matrix3d A;
        for (int i = 0; i < 9; ++i) A(i) = n(rng);
        const Eigen::Matrix3d Q = Eigen::HouseholderQR<Eigen::Matrix3d>(A).householderQ();
        const Eigen::Vector3d e(std::exp(u(rng)), std::exp(u(rng)), std::exp(u(rng)));
        C.block<3, 3>(3 * block, 3 * block) = Q * e.asDiagonal() * Q.transpose();
    }
    return C;
}

Vector6d Draw(const Matrix6d &C, std::mt19937 &rng) {
    std::normal_distribution<double> n;
    Vector6d z;
    for (int i = 0; i < 6; ++i) z(i) = n(rng);
    return Eigen::LLT<Matrix6d>(C).matrixL() * z;
}

NoiseCalibrationConfig On() {
    NoiseCalibrationConfig config;
    config.enabled = true;  // off by default (docs/robust_mapping.md)
    return config;
}

// Innovations with covariance alpha C_p + beta C_r per block, the covariances varying per scan.
NoiseScales Calibrate(const Eigen::Vector2d &alpha, const Eigen::Vector2d &beta, int scans,
                      NoiseCalibrationConfig config = On()) {
    std::mt19937 rng(3);
    NoiseCalibration calibration(config);
    for (int k = 0; k < scans; ++k) {
        const Matrix6d Cp = RandomCovariance(rng, 1e-4, 1e-2);
        const Matrix6d Cr = RandomCovariance(rng, 1e-4, 1e-2);
        const Matrix6d C = ScaleBlocks(Cp, alpha) + ScaleBlocks(Cr, beta);
        calibration.Add(Draw(C, rng), Cp, Cr);
    }
    return calibration.scales();
}

TEST(NoiseCalibration, RecoversTheScalesThatGeneratedTheInnovations) {
    NoiseCalibrationConfig config = On();
    config.window_scans = 20000;  // every sample: the estimate's own noise only
    config.min_scans = 20000;     // solved once, at the end
    // The campus case: a prior that claims 30x the rotation variance it has, a registration that
    // claims half its own.
    const Eigen::Vector2d alpha(0.5, 1.0 / 30.0), beta(1.0, 2.0);
    const NoiseScales s = Calibrate(alpha, beta, 20000, config);
    for (int b = 0; b < 2; ++b) {
        EXPECT_NEAR(s.prior(b) / alpha(b), 1.0, 0.2) << "block " << b;
        EXPECT_NEAR(s.registration(b) / beta(b), 1.0, 0.15) << "block " << b;
    }
}

TEST(NoiseCalibration, HonestModelsKeepTheirScales) {
    const NoiseScales s = Calibrate({1.0, 1.0}, {1.0, 1.0}, 5000);  // default forgetting (100)
    for (int b = 0; b < 2; ++b) {
        EXPECT_NEAR(s.prior(b), 1.0, 0.6) << "block " << b;
        EXPECT_NEAR(s.registration(b), 1.0, 0.6) << "block " << b;
    }
}

TEST(NoiseCalibration, NothingChangesBeforeMinScansOrWhenDisabled) {
    NoiseCalibrationConfig config = On();
    config.min_scans = 50;
    NoiseScales s = Calibrate({0.1, 0.1}, {5.0, 5.0}, 49, config);
    EXPECT_EQ(s.prior, Eigen::Vector2d::Ones());
    EXPECT_EQ(s.registration, Eigen::Vector2d::Ones());
    config.enabled = false;
    s = Calibrate({0.1, 0.1}, {5.0, 5.0}, 500, config);
    EXPECT_EQ(s.registration, Eigen::Vector2d::Ones());
}

TEST(NoiseCalibration, OneOutlierMovesTheScalesLittle) {
    std::mt19937 rng(5);
    NoiseCalibration calibration(On());
    std::vector<std::pair<Matrix6d, Matrix6d>> covariances;
    for (int k = 0; k < 300; ++k) {
        const Matrix6d Cp = RandomCovariance(rng, 1e-4, 1e-2);
        const Matrix6d Cr = RandomCovariance(rng, 1e-4, 1e-2);
        calibration.Add(Draw(Cp + Cr, rng), Cp, Cr);
    }
    const NoiseScales before = calibration.scales();
    const Matrix6d Cp = RandomCovariance(rng, 1e-4, 1e-2);
    calibration.Add(Vector6d::Constant(100.0), Cp, Cp);  // a registration 100 m and rad off
    const NoiseScales after = calibration.scales();
    // Capped at 10 x dof and weighed 1 / 100: each scale moves by well under one.
    EXPECT_LT((after.registration - before.registration).cwiseAbs().maxCoeff(), 0.5);
    EXPECT_LT((after.prior - before.prior).cwiseAbs().maxCoeff(), 0.5);
}

TEST(NoiseCalibration, ScaleBlocksScalesEachBlockAndStaysPositiveDefinite) {
    std::mt19937 rng(9);
    Matrix6d C = RandomCovariance(rng, 1e-3, 1.0);
    C.block<3, 3>(0, 3) = Eigen::Matrix3d::Constant(0.01);
    C.block<3, 3>(3, 0) = C.block<3, 3>(0, 3).transpose();
    const Matrix6d S = ScaleBlocks(C, {4.0, 0.25});
    const Eigen::Matrix3d tt = S.topLeftCorner<3, 3>(), rr = S.bottomRightCorner<3, 3>();
    const Eigen::Matrix3d tr = S.topRightCorner<3, 3>();
    EXPECT_TRUE(tt.isApprox(4.0 * C.topLeftCorner<3, 3>()));
    EXPECT_TRUE(rr.isApprox(0.25 * C.bottomRightCorner<3, 3>()));
    EXPECT_TRUE(tr.isApprox(C.topRightCorner<3, 3>()));  // sqrt(4 x 0.25) = 1
    if (Eigen::SelfAdjointEigenSolver<Matrix6d>(C).eigenvalues().minCoeff() > 0.0) {
        EXPECT_GT(Eigen::SelfAdjointEigenSolver<Matrix6d>(S).eigenvalues().minCoeff(), 0.0);
    }
}

}  // namespace
}  // namespace dorado::mapping
