// Calibration (section IV-A) on simulated per-scan velocities with a known mounting.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/odometry/calibration.hpp"

namespace dorado::odometry {
namespace {

const Eigen::Matrix3d kTrueR = (Eigen::AngleAxisd(0.17, Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(0.09, Eigen::Vector3d::UnitY()) *
                                Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitX()))
                                   .toRotationMatrix();
const Eigen::Vector3d kS(1.1, 0.05, 0.6);

class CalibrationSeeds : public ::testing::TestWithParam<int> {};

TEST_P(CalibrationSeeds, TwoStepRotationRecoversTheMounting) {
    std::mt19937 rng(GetParam());
    std::normal_distribution<double> noise(0.0, 0.02);
    std::uniform_real_distribution<double> speed(-2.0, 2.0), yaw(-0.6, 0.6);
    const auto to_radar = [&](const Eigen::Vector3d &v_s_base) {
        return Eigen::Vector3d(kTrueR.transpose() * v_s_base +
                               Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
    };
    std::vector<Eigen::Vector3d> straight, free_drive;
    for (int i = 0; i < 300; ++i) straight.push_back(to_radar({speed(rng), 0.0, 0.0}));
    for (int i = 0; i < 300; ++i) {  // flat ground: v_base = (v, 0, 0), omega = (0, 0, w)
        const Eigen::Vector3d omega(0, 0, yaw(rng));
        free_drive.push_back(
            to_radar(Eigen::Vector3d(std::abs(speed(rng)) + 0.5, 0, 0) + omega.cross(kS)));
    }
    // Start from a guess with the wrong roll: step 2 must fix it.
    const auto step1 = CalibrateRotation(straight);
    const auto step2 = CalibrateRoll(free_drive, step1.R_base_radar);
    const double error = RotationAngle(step2.R_base_radar * kTrueR.transpose());
    std::printf("rotation error %.4f deg (step 1 sigma %.4f deg, step 2 sigma %.4f deg)\n",
                RadToDeg(error), RadToDeg(step1.sigma_rad), RadToDeg(step2.sigma_rad));
    // Within 4 sigma of the reported uncertainties, and small in absolute terms.
    EXPECT_LT(error, 4.0 * std::hypot(step1.sigma_rad, step2.sigma_rad));
    EXPECT_LT(error, DegToRad(0.8));
    // Forward axis from step 1 alone is already right.
    EXPECT_GT((step1.R_base_radar * kTrueR.transpose().col(0)).x(), 0.99999);
    EXPECT_NEAR(step1.rms_residual_mps, 0.02, 0.004);
    EXPECT_THROW(CalibrateRoll(straight, step1.R_base_radar), std::invalid_argument)
        << "straight driving cannot determine the roll";
}

INSTANTIATE_TEST_SUITE_P(Seeds, CalibrationSeeds, ::testing::Values(5, 6, 7, 8));

TEST(Calibration, SxFromGyroWithOutliers) {
    std::mt19937 rng(9);
    std::normal_distribution<double> noise(0.0, 0.03), gyro_noise(0.0, 0.005);
    std::uniform_real_distribution<double> yaw(0.3, 0.6);
    std::vector<Eigen::Vector3d> v;
    std::vector<double> w;
    for (int i = 0; i < 400; ++i) {
        const double wz = yaw(rng);
        Eigen::Vector3d v_s(1.0, wz * kS.x() + noise(rng), noise(rng));
        if (i % 20 == 0) v_s.y() += 1.5;  // 5 % scans with a bad velocity
        v.push_back(v_s);
        w.push_back(wz + gyro_noise(rng));
    }
    const auto c = CalibrateSx(v, w);
    std::printf("s_x %.4f +- %.4f m (true %.4f), %d of %d inliers\n", c.s_x_m, c.sigma_m, kS.x(),
                c.inliers, c.samples);
    EXPECT_NEAR(c.s_x_m, kS.x(), 4 * c.sigma_m);
    EXPECT_LT(c.sigma_m, 0.02);
    EXPECT_GE(c.inliers, 375);
    EXPECT_LE(c.inliers, 382);
    EXPECT_THROW(static_cast<void>(CalibrateSx(v, std::vector<double>(v.size(), 0.0))),
                 std::invalid_argument);
}

}  // namespace
}  // namespace dorado::odometry
