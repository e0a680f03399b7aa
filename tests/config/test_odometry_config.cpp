// configs/odometry.yaml's ground section: a bad value or an unknown key is an error naming the file
// and the key (test_config_fields.cpp reads every key back).
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "dorado/config/odometry_config.hpp"

namespace dorado::config {
namespace {

std::string Write(const std::string &name, const std::string &text) {
    const std::string path = ::testing::TempDir() + name;
    std::ofstream(path) << text;
    return path;
}

std::string ErrorOf(const std::string &path) {
    try {
        (void)LoadOdometryConfig(path);
    } catch (const std::exception &e) {
        return e.what();
    }
    return "";
}

TEST(OdometryConfig, GroundErrorsNameTheFileAndTheKey) {
    const std::string bad =
        Write("ground_bad.yaml", "ground:\n  enabled: true\n  max_tilt_deg: 75\n");
    const std::string message = ErrorOf(bad);
    EXPECT_NE(message.find(bad), std::string::npos) << message;
    EXPECT_NE(message.find("ground.max_tilt_deg"), std::string::npos) << message;

    const std::string unknown = Write("ground_unknown.yaml", "ground:\n  min_point: 10\n");
    EXPECT_NE(ErrorOf(unknown).find("min_point"), std::string::npos) << ErrorOf(unknown);

    const std::string ok = Write("ground_ok.yaml", "ground:\n  enabled: true\n  min_points: 50\n");
    EXPECT_EQ(LoadOdometryConfig(ok).ground.plane.min_points, 50);
}

TEST(OdometryConfig, OnlineCalibrationKeysAreReadAndShippedAtTheirDefaults) {
    const odometry::YawCalibrationConfig defaults;
    const auto shipped =
        LoadOdometryConfig(DORADO_SOURCE_DIR "/configs/odometry.yaml").online_calibration;
    EXPECT_EQ(shipped.enabled, defaults.enabled);
    EXPECT_DOUBLE_EQ(shipped.warmup_s, defaults.warmup_s);
    EXPECT_DOUBLE_EQ(shipped.window_s, defaults.window_s);
    EXPECT_DOUBLE_EQ(shipped.max_window_s, defaults.max_window_s);
    EXPECT_DOUBLE_EQ(shipped.min_turn_rad, defaults.min_turn_rad);
    EXPECT_DOUBLE_EQ(shipped.min_speed_mps, defaults.min_speed_mps);
    EXPECT_DOUBLE_EQ(shipped.measurement_sigma_rad, defaults.measurement_sigma_rad);
    EXPECT_DOUBLE_EQ(shipped.relative_sigma, defaults.relative_sigma);
    EXPECT_DOUBLE_EQ(shipped.initial_relative_sigma, defaults.initial_relative_sigma);
    EXPECT_DOUBLE_EQ(shipped.relative_random_walk_per_sqrt_s,
                     defaults.relative_random_walk_per_sqrt_s);
    EXPECT_DOUBLE_EQ(shipped.max_innovation_chi2, defaults.max_innovation_chi2);
    EXPECT_DOUBLE_EQ(shipped.max_ratio, defaults.max_ratio);

    const std::string set = Write("calib_set.yaml",
                                  "online_calibration:\n  enabled: true\n  window_s: 2.5\n"
                                  "  max_window_s: 6\n  min_turn_rad: 0.1\n");
    const auto read = LoadOdometryConfig(set).online_calibration;
    EXPECT_TRUE(read.enabled);
    EXPECT_DOUBLE_EQ(read.window_s, 2.5);
    EXPECT_DOUBLE_EQ(read.max_window_s, 6.0);
    EXPECT_DOUBLE_EQ(read.min_turn_rad, 0.1);

    const std::string bad = Write("calib_bad.yaml", "online_calibration:\n  max_ratio: 0.5\n");
    EXPECT_NE(ErrorOf(bad).find("online_calibration.max_ratio"), std::string::npos)
        << ErrorOf(bad);
}

}  // namespace
}  // namespace dorado::config
