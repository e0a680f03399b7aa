// dorado_ros2's command line and parameters as rcl reads them (ros2/node/ros2_args.hpp,
// ros2_params.hpp): `--ros-args --params-file FILE -r FROM:=TO -p NAME:=VALUE`, the YAML layout
// `<node>:` / `/**:` + `ros__parameters:`, and the shared NodeSettings read from it.
#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>

#include "dorado/io/config_error.hpp"
#include "node_settings.hpp"
#include "ros2_args.hpp"
#include "ros2_params.hpp"

namespace dorado::ros2 {
namespace {

RosArgs Parse(std::vector<const char *> argv) {
    argv.insert(argv.begin(), "dorado_ros2");
    return ParseRosArgs(static_cast<int>(argv.size()), argv.data());
}

std::string WriteFile(const std::string &name, const std::string &text) {
    const auto path = std::filesystem::path(::testing::TempDir()) /
                      (name + "_" + std::to_string(getpid()) + ".yaml");
    std::ofstream(path) << text;
    return path.string();
}

TEST(Ros2Args, RosArgsAsRclReadsThem) {
    const RosArgs args =
        Parse({"--ros-args", "--params-file", "a.yaml", "-r", "/hugin_raf_1/radar_data:=/radar",
               "--remap", "__node:=radar_odom", "-p", "mapper:=true", "--"});
    EXPECT_EQ(args.node_name, "radar_odom");
    EXPECT_EQ(args.params_files, std::vector<std::string>{"a.yaml"});
    ASSERT_EQ(args.params.size(), 1u);
    EXPECT_EQ(args.params[0].first, "mapper");
    EXPECT_EQ(Remapped(args, "/hugin_raf_1/radar_data"), "/radar");
    EXPECT_EQ(Remapped(args, "hugin_raf_1/radar_data"), "/radar");  // relative: the root namespace
    EXPECT_EQ(Remapped(args, "/doppler_odom"), "/doppler_odom");
    EXPECT_THROW(Parse({"--params-file", "a.yaml"}), std::invalid_argument);  // before --ros-args
    EXPECT_THROW(Parse({"--ros-args", "-r", "nothing"}), std::invalid_argument);
    EXPECT_THROW(Parse({"--ros-args", "--log-level", "debug"}), std::invalid_argument);
    EXPECT_THROW(Parse({"--ros-args", "-p"}), std::invalid_argument);
}

TEST(Ros2Params, NodeSectionOverWildcardThenMinusP) {
    const std::string file = WriteFile("params", R"(/**:
  ros__parameters:
    queue_size: 4
    verbose: true
dorado_ros2:
  ros__parameters:
    queue_size: 7
    max_gap_s: 2
    input_topic: /radar
    sensor_pose: [0.1, 0, 0, 0, 0, 0, 1]
other_node:
  ros__parameters:
    queue_size: 99
)");
    const RosArgs args =
        Parse({"--ros-args", "--params-file", file.c_str(), "-p", "imu_wait_s:=0.2"});
    const Ros2Params params(args);
    const ros_node::NodeSettings s = ros_node::ReadNodeSettings(params);
    EXPECT_EQ(s.queue_size, 7);
    EXPECT_TRUE(s.verbose);
    EXPECT_EQ(s.gaps.max_gap_s, 2.0);  // an integer where a double is read
    EXPECT_EQ(s.input_topic, "/radar");
    EXPECT_EQ(s.imu_wait_s, 0.2);
    EXPECT_EQ(params.Unknown(ros_node::ParameterNames()), std::vector<std::string>{});
}

TEST(Ros2Params, WrongTypesAndUnknownNamesAreNamed) {
    const std::string file = WriteFile("wrong", R"(dorado_ros2:
  ros__parameters:
    queue_size: many
    queue_sise: 3
)");
    const Ros2Params params(Parse({"--ros-args", "--params-file", file.c_str()}));
    try {
        (void)ros_node::ReadNodeSettings(params);
        ADD_FAILURE() << "queue_size: many was read";
    } catch (const io::ConfigError &e) {
        EXPECT_NE(
            std::string(e.what()).find("parameter 'queue_size' (" + file + "): must be an integer"),
            std::string::npos)
            << e.what();
    }
    const auto unknown = params.Unknown(ros_node::ParameterNames());
    ASSERT_EQ(unknown.size(), 1u);
    EXPECT_NE(unknown[0].find("'queue_sise'"), std::string::npos);
    EXPECT_NE(unknown[0].find("did you mean 'queue_size'?"), std::string::npos) << unknown[0];
}

TEST(Ros2Params, AFileWithoutTheNodesSectionIsRefused) {
    const std::string file = WriteFile("other", "other_node:\n  ros__parameters:\n    a: 1\n");
    try {
        const Ros2Params params(Parse({"--ros-args", "--params-file", file.c_str()}));
        ADD_FAILURE() << "read";
    } catch (const io::ConfigError &e) {
        EXPECT_NE(std::string(e.what()).find("no section for node 'dorado_ros2'"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_THROW(Ros2Params(Parse({"--ros-args", "--params-file", "/nonexistent.yaml"})),
                 io::ConfigError);
}

}  // namespace
}  // namespace dorado::ros2
