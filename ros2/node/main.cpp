// dorado_ros2: the live node of dorado_ros for ROS 2, on Cyclone DDS (no rclcpp): the same
// parameters, topics, faults handling and summary. docs/live_node.md, "ROS 2".
#include <csignal>
#include <cstdio>
#include <exception>

#include "dorado/io/config_error.hpp"
#include "node_settings.hpp"
#include "ros2_args.hpp"
#include "ros2_node.hpp"
#include "ros2_params.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;

void OnSignal(int) {
    g_stop = 1;
}

constexpr const char *kUsage =
    "usage: dorado_ros2 [--ros-args [--params-file FILE] [-r FROM:=TO] [-r __node:=NAME] "
    "[-p NAME:=VALUE] [--]]\n"
    "The live radar odometry and mapping node for ROS 2 (Cyclone DDS; domain ROS_DOMAIN_ID).\n"
    "Parameters (docs/live_node.md) from FILE in ROS 2's layout (NODE: ros__parameters: ...) and\n"
    "-p; topic names remapped with -r. SIGINT or SIGTERM: stop, print and write the summary.\n";

}  // namespace

int main(int argc, char **argv) {
    using namespace dorado;
    try {
        const ros2::RosArgs args = ros2::ParseRosArgs(argc, argv);
        if (args.help) {
            std::fputs(kUsage, stdout);
            return 0;
        }
        const ros2::Ros2Params params(args);
        for (const std::string &unknown : params.Unknown([] {
                 auto known = ros_node::ParameterNames();
                 known.push_back("use_sim_time");
                 return known;
             }()))
            std::fprintf(stderr, "[WARN] %s: parameter %s is not one of the node's (ignored)\n",
                         args.node_name.c_str(), unknown.c_str());
        bool use_sim_time = false;
        params.Get("use_sim_time", use_sim_time);
        std::signal(SIGINT, OnSignal);
        std::signal(SIGTERM, OnSignal);
        ros2::Ros2Node node(args, ros_node::ReadNodeSettings(params), use_sim_time);
        while (!g_stop) {
            struct timespec pause {
                0, 50000000
            };
            nanosleep(&pause, nullptr);
        }
        node.Shutdown();
    } catch (const std::exception &e) {
        std::fprintf(stderr, "dorado_ros2: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
