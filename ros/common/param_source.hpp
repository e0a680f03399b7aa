#pragma once
/// @file param_source.hpp
/// Where a live node's parameters come from, without ROS: the ROS1 parameter server
/// (ros/src/ros1_params.cpp) or a ROS 2 `--params-file` YAML (ros2/src/ros2_params.cpp). Each
/// getter returns false when the parameter is not set and throws io::ConfigError naming it when it
/// is set with the wrong type.

#include <string>
#include <vector>

namespace dorado::ros_node {

class ParamSource {
  public:
    virtual ~ParamSource() = default;
    virtual bool Get(const std::string &name, std::string &value) const = 0;
    virtual bool Get(const std::string &name, bool &value) const = 0;
    virtual bool Get(const std::string &name, int &value) const = 0;
    /// An integer is taken as a double.
    virtual bool Get(const std::string &name, double &value) const = 0;
    /// A list of numbers (integers or doubles), of any length (the caller checks it).
    virtual bool GetNumbers(const std::string &name, std::vector<double> &values) const = 0;
};

}  // namespace dorado::ros_node
