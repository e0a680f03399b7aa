#pragma once
/// @file ros1_params.hpp
/// The ROS1 parameter server as a ParamSource: private `~name` first, then `name` in the node's
/// namespace (where the paper's launch file sets them).

#include <ros/ros.h>

#include "param_source.hpp"

namespace dorado::ros_node {

class Ros1Params : public ParamSource {
  public:
    Ros1Params(const ros::NodeHandle &node, const ros::NodeHandle &private_node)
        : node_(node), private_(private_node) {}

    bool Get(const std::string &name, std::string &value) const override;
    bool Get(const std::string &name, bool &value) const override;
    bool Get(const std::string &name, int &value) const override;
    bool Get(const std::string &name, double &value) const override;
    bool GetNumbers(const std::string &name, std::vector<double> &values) const override;

  private:
    const ros::NodeHandle *Which(const std::string &name) const;
    template <typename T>
    bool GetValue(const std::string &name, T &value) const;

    const ros::NodeHandle &node_;
    const ros::NodeHandle &private_;
};

}  // namespace dorado::ros_node
