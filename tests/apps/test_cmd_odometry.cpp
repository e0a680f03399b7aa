// `dorado odometry` and `dorado calibrate` end to end on a bag written by the real ROS tools
// (make_odometry_bag.py): a vehicle driving a flat circle with a known constant twist.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/core/time.hpp"
#include "dorado/io/trajectory_io.hpp"

namespace {

namespace fs = std::filesystem;

// Field k of a CSV row (quoted fields may hold commas).
std::string CsvField(const std::string &row, std::size_t k) {
    std::string field;
    std::size_t index = 0;
    bool quoted = false;
    for (char c : row) {
        if (c == '"') quoted = !quoted;
        if (c == ',' && !quoted) {
            if (index++ == k) return field;
            field.clear();
        } else {
            field += c;
        }
    }
    return index == k ? field : std::string();
}

std::size_t CsvColumn(const std::string &header, const std::string &name) {
    for (std::size_t k = 0;; ++k) {
        const std::string field = CsvField(header, k);
        if (field == name || field.empty()) return k;
    }
}

class CmdOdometry : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        dir_ =
            fs::path(::testing::TempDir()) / ("dorado_cmd_odometry_" + std::to_string(::getpid()));
        const std::string cmd = std::string(DORADO_SYSTEM_PYTHON) + " " + DORADO_SOURCE_DIR +
                                "/tests/apps/make_odometry_bag.py " + dir_.string();
        ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    }
    static void TearDownTestSuite() { fs::remove_all(dir_); }

    // Runs dorado with the arguments; returns the exit code, stderr in `err`.
    static int Dorado(const std::string &args, std::string *err = nullptr,
                      const std::string &environment = "") {
        const std::string log = (dir_ / "stderr.txt").string();
        const std::string cmd =
            environment + std::string(DORADO_BINARY) + " " + args + " 2> " + log;
        const int status = std::system(cmd.c_str());
        std::ifstream in(log);
        std::stringstream ss;
        ss << in.rdbuf();
        if (err) *err = ss.str();
        return WEXITSTATUS(status);
    }
    static std::string Dataset() { return (dir_ / "dataset.yaml").string(); }
    static fs::path dir_;
};
fs::path CmdOdometry::dir_;

// The truth: constant speed 2 m/s and yaw rate 0.4 rad/s from the first scan on.
Eigen::Isometry3d TruePose(double t_s) {
    dorado::Vector6d xi;
    xi << 2.0, 0, 0, 0, 0, 0.4;
    return dorado::ExpSE3(xi * t_s);
}

TEST_F(CmdOdometry, DopplerOdometryFollowsTheCircleAndReportsTheBadScan) {
    const fs::path out = dir_ / "doppler";
    std::string err;
    ASSERT_EQ(Dorado("odometry " + Dataset() + " --out " + out.string() + " --masks", &err), 0)
        << err;
    const auto trajectory = dorado::io::ReadTum((out / "trajectory.tum").string());
    ASSERT_EQ(trajectory.size(), 60u);
    const auto &first = trajectory[0], &last = trajectory[trajectory.size() - 1];
    const double T = dorado::NanosToSeconds(last.stamp_ns - first.stamp_ns);
    const Eigen::Isometry3d truth = TruePose(T);
    const double position_error = (last.T_world_body.translation() - truth.translation()).norm();
    const double yaw_error =
        dorado::RotationAngle(last.T_world_body.linear().transpose() * truth.linear());
    std::printf("Doppler-only after %.1f s: %.3f m, %.3f deg\n", T, position_error,
                dorado::RadToDeg(yaw_error));
    EXPECT_LT(position_error, 0.15);  // 11.8 m of path
    EXPECT_LT(yaw_error, 0.03);

    const auto summary = nlohmann::json::parse(std::ifstream(out / "summary.json"));
    EXPECT_EQ(summary["scans"], 60);
    EXPECT_EQ(summary["scans_with_fallback_twist"], 1);
    EXPECT_EQ(summary["fallback_causes"]["invalid_velocity"], 1);  // the bad scan, by cause
    EXPECT_TRUE(summary["stopped_early"].is_null());               // ran to the end
    EXPECT_NEAR(summary["inlier_ratio"]["median"].get<double>(), 0.8, 0.01);  // 20 % moving

    std::ifstream csv(out / "velocities.csv");
    std::string header, line;
    std::getline(csv, header);
    EXPECT_EQ(header.rfind("t,v_radar_x,v_radar_y,v_radar_z,cov_v_xx", 0), 0u);
    EXPECT_NE(header.find("gyro_base_x,gyro_base_y,gyro_base_z,time_ms,cov_omega_model_xx"),
              std::string::npos);
    EXPECT_NE(header.find("cov_omega_model_zz,fallback_cause,zero_velocity_update"),
              std::string::npos);
    int rows = 0, invalid = 0;
    // The model's yaw-rate variance with the default vehicle.model_noise, by hand: the rear axle's
    // lateral velocity (ICR 0.1 m * |w|, slip 0.005 * v^2 * |w|, 0.02 m/s) over s_x, and the
    // unobserved roll rate (0.05 rad/s) through the lever arm s_z / s_x (make_odometry_bag.py).
    const double w = 0.4, v = 2.0, s_x = 0.9, s_z = 0.6;
    const double lateral = std::pow(0.1 * w, 2) + std::pow(0.005 * v * v * w, 2) + 0.02 * 0.02;
    const double expected_zz = lateral / (s_x * s_x) + std::pow(s_z / s_x * 0.05, 2);
    while (std::getline(csv, line)) {
        ++rows;
        invalid += line.find(",0,\"") != std::string::npos;
        if (rows == 20) {  // the columns by their names (more columns may follow them)
            EXPECT_NEAR(std::stod(CsvField(line, CsvColumn(header, "cov_omega_model_zz"))),
                        expected_zz, 0.05 * expected_zz);
            // its own twist, moving
            EXPECT_EQ(CsvField(line, CsvColumn(header, "fallback_cause")), "none") << line;
            EXPECT_EQ(CsvField(line, CsvColumn(header, "zero_velocity_update")), "0") << line;
        }
    }
    EXPECT_EQ(rows, 60);
    EXPECT_EQ(invalid, 1);

    // Masks: 400 labels per scan, the first 80 points (the crossing car) dynamic.
    std::ifstream mask(out / "masks" / "000010.txt");
    std::getline(mask, line);
    int dynamic = 0, total = 0, label;
    while (mask >> label) dynamic += (total++ < 80) == (label == 1);
    EXPECT_EQ(total, 400);
    EXPECT_GE(dynamic, 390);
}

TEST_F(CmdOdometry, ImuRotationAndImuOnly) {
    for (const std::string mode : {"imu+doppler", "imu"}) {
        const fs::path out = dir_ / mode;
        std::string err;
        ASSERT_EQ(
            Dorado("odometry " + Dataset() + " --method " + mode + " --out " + out.string(), &err),
            0)
            << err;
        const auto trajectory = dorado::io::ReadTum((out / "trajectory.tum").string());
        const auto &last = trajectory[trajectory.size() - 1];
        const double T = dorado::NanosToSeconds(last.stamp_ns - trajectory[0].stamp_ns);
        // The gyro is exact here, so the rotation is (up to the first interval without IMU).
        EXPECT_NEAR(dorado::RotationAngle(last.T_world_body.linear()), 0.4 * T, 0.05) << mode;
        if (mode == "imu")
            EXPECT_LT(last.T_world_body.translation().norm(), 1e-9);
        else
            EXPECT_LT((last.T_world_body.translation() - TruePose(T).translation()).norm(), 0.3);
    }
}

// The bag's 6 s circle turns 137 deg: refused (a circle needs 270); with --no-drive-checks the
// estimate is written, and it is right (the data is exact).
TEST_F(CmdOdometry, CalibrateSxRecoversTheLeverArm) {
    const fs::path out = dir_ / "sx.yaml";
    std::string err;
    ASSERT_EQ(Dorado("calibrate sx " + Dataset() + " --out " + out.string(), &err), 1) << err;
    EXPECT_NE(err.find("calibrate sx refused: the vehicle turned 1"), std::string::npos) << err;
    EXPECT_NE(err.find("s_x needs a circle (at least 270 deg of turning)"), std::string::npos)
        << err;
    EXPECT_FALSE(fs::exists(out));
    ASSERT_EQ(
        Dorado("calibrate sx " + Dataset() + " --no-drive-checks --out " + out.string(), &err), 0)
        << err;
    std::ifstream in(out);
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string yaml = ss.str();
    const auto pos = yaml.find("translation_m: [");
    ASSERT_NE(pos, std::string::npos) << yaml;
    const double s_x = std::stod(yaml.substr(pos + 16));
    EXPECT_NEAR(s_x, 0.9, 0.02) << yaml;
    EXPECT_NE(yaml.find("rotation_rpy_deg: [0, 0, 10"), std::string::npos) << yaml;
}

// Ctrl-C in the middle of a run (a real SIGINT, raised by the process itself after scan 25 through
// the test hook): the scans done so far are written, the summary says why it stopped, exit 130.
TEST_F(CmdOdometry, InterruptWritesTheScansDoneAndExits130) {
    for (const std::string command : {"odometry", "map"}) {
        const fs::path out = dir_ / ("interrupted_" + command);
        std::string err;
        const std::string args = command + " " + Dataset() + " --out " + out.string() +
                                 (command == "map" ? " --prior doppler" : "");
        EXPECT_EQ(Dorado(args, &err, "DORADO_TEST_SIGINT_AFTER_SCANS=25 "), 130) << err;
        EXPECT_NE(err.find(command + " stopped early after 25 scans: interrupted (SIGINT)"),
                  std::string::npos)
            << err;
        const auto trajectory = dorado::io::ReadTum((out / "trajectory.tum").string());
        EXPECT_EQ(trajectory.size(), 25u) << command;
        for (std::size_t i = 0; i < trajectory.size(); ++i)
            EXPECT_TRUE(trajectory[i].T_world_body.matrix().allFinite());
        const auto summary = nlohmann::json::parse(std::ifstream(out / "summary.json"));
        EXPECT_EQ(summary["scans"], 25) << command;
        EXPECT_EQ(summary["stopped_early"], "interrupted (SIGINT)") << command;
    }
}

TEST_F(CmdOdometry, BadInputGivesOneClearError) {
    std::ofstream(dir_ / "bad.yaml") << "ego_velocity:\n  gate_sigma: 3\n";
    std::string err;
    EXPECT_EQ(Dorado("odometry " + Dataset() + " --out " + (dir_ / "x").string() + " --config " +
                         (dir_ / "bad.yaml").string(),
                     &err),
              1);
    EXPECT_NE(err.find("bad.yaml: key 'ego_velocity.gate_sigma': unknown key"), std::string::npos)
        << err;
    std::ofstream(dir_ / "bad2.yaml") << "ego_velocity:\n  gate_sigmas: -3\n";
    EXPECT_EQ(Dorado("odometry " + Dataset() + " --out " + (dir_ / "x").string() + " --config " +
                         (dir_ / "bad2.yaml").string(),
                     &err),
              1);
    EXPECT_NE(err.find("key 'ego_velocity.gate_sigmas': must be > 0"), std::string::npos) << err;
    EXPECT_EQ(Dorado("calibrate roll " + (dir_ / "missing.bag").string() + " --out x.yaml", &err),
              1);
    EXPECT_NE(err.find("dorado: error:"), std::string::npos) << err;
}

// A wrong field map (fields.doppler names no channel) makes every scan unreadable: refused on the
// first scans, before --out is touched, in one line naming the field; not one warning per scan.
TEST_F(CmdOdometry, AWrongFieldMapIsSummarisedNotOneLinePerScan) {
    std::ifstream in(Dataset());
    std::stringstream yaml;
    yaml << in.rdbuf() << "fields:\n  doppler: dopler\n";
    std::ofstream(dir_ / "wrong_field.yaml") << yaml.str();
    std::string err;
    EXPECT_EQ(Dorado("odometry " + (dir_ / "wrong_field.yaml").string() + " --out " +
                         (dir_ / "wrong_field").string(),
                     &err),
              1);
    const auto lines = std::count(err.begin(), err.end(), '\n');
    EXPECT_LE(lines, 8) << err;
    EXPECT_NE(err.find("missing field 'dopler'"), std::string::npos) << err;
    EXPECT_NE(err.find("the first 10 radar scans cannot be read"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(dir_ / "wrong_field" / "summary.json"));
    EXPECT_NE(err.find("dorado: error:"), std::string::npos) << err;
}

}  // namespace
