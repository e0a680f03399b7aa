// A bare .bag is read with the paper's Hugin defaults, mount included: a bag
// mounted as the paper's Hugin (make_hugin_mount_bag.py, which derives the mount from the launch
// values on its own) gives the vehicle's true velocity through `dorado odometry data.bag`.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "dorado/core/lie.hpp"
#include "dorado/core/paper_mount.hpp"
#include "dorado/core/time.hpp"
#include "dorado/io/trajectory_io.hpp"

namespace {

namespace fs = std::filesystem;

std::vector<std::string> SplitCsv(const std::string &line) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    return cells;
}

TEST(BareBagHugin, TheLaunchFileMountGivesTheTrueVelocity) {
    const fs::path dir =
        fs::path(::testing::TempDir()) / ("dorado_bare_bag_" + std::to_string(::getpid()));
    const std::string make = std::string(DORADO_SYSTEM_PYTHON) + " " + DORADO_SOURCE_DIR +
                             "/tests/apps/make_hugin_mount_bag.py " + dir.string();
    ASSERT_EQ(std::system(make.c_str()), 0) << make;
    const fs::path out = dir / "out";
    const std::string run = std::string(DORADO_BINARY) + " odometry " +
                            (dir / "data.bag").string() + " --out " + out.string() + " 2> " +
                            (dir / "stderr.txt").string();
    ASSERT_EQ(std::system(run.c_str()), 0) << run;

    // The truth (make_hugin_mount_bag.py): v_base = (1.5, 0, 0), omega = (0, 0.05, 0.3).
    std::ifstream csv(out / "velocities.csv");
    std::string line;
    std::getline(csv, line);
    const auto header = SplitCsv(line);
    auto column = [&](const std::string &name) {
        for (size_t i = 0; i < header.size(); ++i)
            if (header[i] == name) return i;
        ADD_FAILURE() << "no column " << name;
        return size_t{0};
    };
    const size_t vx = column("v_base_x"), vy = column("v_base_y"), vz = column("v_base_z");
    const size_t wy = column("omega_base_y"), wz = column("omega_base_z");
    // Every scan near the truth (the pitch rate is the noisiest: v_sz over a 1 m lever arm), and
    // the means tight: the calibration composed the other way round (R_s R_c) is 2 deg off,
    // 0.05 m/s of v_sy, 0.05 rad/s of yaw rate.
    int rows = 0;
    double sum_vx = 0, sum_vy = 0, sum_vz = 0, sum_wy = 0, sum_wz = 0;
    while (std::getline(csv, line)) {
        const auto cells = SplitCsv(line);
        ++rows;
        sum_vx += std::stod(cells[vx]);
        sum_vy += std::stod(cells[vy]);
        sum_vz += std::stod(cells[vz]);
        sum_wy += std::stod(cells[wy]);
        sum_wz += std::stod(cells[wz]);
        EXPECT_NEAR(std::stod(cells[vx]), 1.5, 0.03) << line;
        EXPECT_NEAR(std::stod(cells[wy]), 0.05, 0.05) << line;
        EXPECT_NEAR(std::stod(cells[wz]), 0.3, 0.02) << line;
    }
    ASSERT_GT(rows, 0);
    EXPECT_NEAR(sum_vx / rows, 1.5, 0.005);
    EXPECT_NEAR(sum_vy / rows, 0.0, 0.005);
    EXPECT_NEAR(sum_vz / rows, 0.0, 0.005);
    EXPECT_NEAR(sum_wy / rows, 0.05, 0.01);
    EXPECT_NEAR(sum_wz / rows, 0.3, 0.005);
    EXPECT_EQ(rows, 50);

    // The pose after 4.9 s against the constant twist's exponential.
    const auto trajectory = dorado::io::ReadTum((out / "trajectory.tum").string());
    ASSERT_EQ(trajectory.size(), 50u);
    const auto &first = trajectory[0], &last = trajectory[trajectory.size() - 1];
    const double T = dorado::NanosToSeconds(last.stamp_ns - first.stamp_ns);
    dorado::Vector6d xi;
    xi << 1.5, 0, 0, 0, 0.05, 0.3;
    const Eigen::Isometry3d truth = first.T_world_body * dorado::ExpSE3(xi * T);
    EXPECT_LT((last.T_world_body.translation() - truth.translation()).norm(), 0.1);
    // 0.03 rad: the angular-rate prior (0.2 rad/s) pulls the steady 0.05 rad/s pitch rate a few
    // percent towards zero (0.023 rad after 4.9 s); the calibration composed the wrong way round
    // is 0.05 rad/s of yaw rate, 0.25 rad.
    EXPECT_LT(dorado::RotationAngle(last.T_world_body.linear().transpose() * truth.linear()), 0.03);
    fs::remove_all(dir);
}

// The derivation in configs/hugin.yaml, by numbers: the radar 0.99447 m ahead of the ICR, the
// paper's base_link 0.14447 m ahead of it, and R = R(calib_rot) R(sensor_rot).
TEST(PaperMount, ComposesTheCalibrationAfterTheMount) {
    const dorado::PaperMountParameters p;
    const dorado::PaperMount mount = dorado::MountFromPaperParameters(p);
    const Eigen::Vector3d s = mount.extrinsics.T_base_radar.translation();
    EXPECT_NEAR(s.x(), 0.9944683540059478, 1e-12);
    EXPECT_NEAR(s.y(), 0.22, 1e-12);
    EXPECT_NEAR(s.z(), 0.17, 1e-12);
    EXPECT_NEAR(mount.T_base_baselink.translation().x(), 0.9944683540059478 - 0.85, 1e-12);
    EXPECT_EQ(mount.half_wheelbase_m, 0.0);
    // The radar's Y axis points forward, its Z axis down (quaternion in configs/hugin.yaml).
    const Eigen::Matrix3d R = mount.extrinsics.T_base_radar.linear();
    const Eigen::Quaterniond q(R);
    EXPECT_NEAR(std::abs(q.dot(Eigen::Quaterniond(0.02130412, 0.67295128, 0.73916614, 0.01777985))),
                1.0, 1e-7);
    EXPECT_GT(R(0, 1), 0.99);
    EXPECT_LT(R(2, 2), -0.99);
}

}  // namespace
