#pragma once
/// @file ros2_args.hpp
/// A ROS 2 node's command line, as rcl reads it: `--ros-args` then `--params-file FILE`,
/// `-r/--remap FROM:=TO` (a topic name, or `__node:=NAME`), `-p/--param NAME:=VALUE`, up to `--`.

#include <string>
#include <utility>
#include <vector>

namespace dorado::ros2 {

struct RosArgs {
    std::string node_name = "dorado_ros2";
    std::vector<std::string> params_files;
    std::vector<std::pair<std::string, std::string>> remaps;  ///< topic name from, to
    std::vector<std::pair<std::string, std::string>> params;  ///< name, YAML value
    bool help = false;
};

/// Throws std::invalid_argument naming the argument that is not understood.
[[nodiscard]] RosArgs ParseRosArgs(int argc, const char *const *argv);

/// The topic name after the remaps (the first rule that matches, as rcl applies them).
[[nodiscard]] std::string Remapped(const RosArgs &args, const std::string &topic);

}  // namespace dorado::ros2
