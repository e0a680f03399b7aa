// dorado_ros: the live ROS1 node, a drop-in for the paper's doppler_odometry_node (same
// parameters, /doppler_odom and the TF) with dorado's front end behind it. See README.md.
#include <ros/ros.h>

#include <cstdio>

#include "dorado_node.hpp"
#include "node_settings.hpp"
#include "ros1_params.hpp"

int main(int argc, char **argv) {
    ros::init(argc, argv, "dorado_ros");  // roscpp's SIGINT handler: a clean ros::shutdown
    ros::NodeHandle node, private_node("~");
    try {
        const dorado::ros_node::Ros1Params params(node, private_node);
        dorado::ros_node::DoradoNode dorado(node, dorado::ros_node::ReadNodeSettings(params));
        ros::AsyncSpinner spinner(2);
        spinner.start();
        ros::waitForShutdown();
        spinner.stop();
        dorado.Shutdown();
    } catch (const std::exception &e) {
        ROS_FATAL("dorado_ros: %s", e.what());
        std::fprintf(stderr, "dorado_ros: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
