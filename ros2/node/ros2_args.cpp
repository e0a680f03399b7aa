#include "ros2_args.hpp"

#include <stdexcept>

namespace dorado::ros2 {
namespace {

std::pair<std::string, std::string> Rule(const std::string &flag, const std::string &text) {
    const std::size_t at = text.find(":=");
    if (at == std::string::npos || at == 0 || at + 2 == text.size())
        throw std::invalid_argument(flag + " " + text + ": expected NAME:=VALUE");
    return {text.substr(0, at), text.substr(at + 2)};
}

}  // namespace

RosArgs ParseRosArgs(int argc, const char *const *argv) {
    RosArgs args;
    bool in_ros_args = false;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "-h" || arg == "--help") {
            args.help = true;
            continue;
        }
        if (arg == "--ros-args") {
            in_ros_args = true;
            continue;
        }
        if (arg == "--") {
            in_ros_args = false;
            continue;
        }
        if (!in_ros_args)
            throw std::invalid_argument("unknown argument '" + arg +
                                        "' (parameters and remaps go after --ros-args)");
        const bool takes_value = arg == "--params-file" || arg == "-r" || arg == "--remap" ||
                                 arg == "-p" || arg == "--param";
        if (!takes_value)
            throw std::invalid_argument("unknown ROS argument '" + arg +
                                        "' (dorado_ros2 reads --params-file, -r, -p)");
        if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
        const std::string value = argv[++i];
        if (arg == "--params-file") {
            args.params_files.push_back(value);
        } else if (arg == "-p" || arg == "--param") {
            args.params.push_back(Rule(arg, value));
        } else {
            auto rule = Rule(arg, value);
            if (rule.first == "__node" || rule.first == "__name")
                args.node_name = rule.second;
            else
                args.remaps.push_back(std::move(rule));
        }
    }
    return args;
}

std::string Remapped(const RosArgs &args, const std::string &topic) {
    // A rule names the topic as given or fully qualified (a relative name is in the root
    // namespace).
    auto qualified = [](const std::string &name) {
        return !name.empty() && name[0] == '/' ? name : "/" + name;
    };
    for (const auto &[from, to] : args.remaps)
        if (qualified(from) == qualified(topic)) return qualified(to);
    return topic;
}

}  // namespace dorado::ros2
