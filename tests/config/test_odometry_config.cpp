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

}  // namespace
}  // namespace dorado::config
