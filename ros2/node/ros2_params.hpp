#pragma once
/// @file ros2_params.hpp
/// ROS 2 parameters as a ParamSource: the `--params-file` YAML files in ROS 2's layout
/// (`<node>:` or `/**:` then `ros__parameters:`, nested maps joined with '.'), then the `-p`
/// overrides, later ones winning.

#include <yaml-cpp/yaml.h>

#include <map>
#include <string>
#include <vector>

#include "param_source.hpp"
#include "ros2_args.hpp"

namespace dorado::ros2 {

class Ros2Params : public ros_node::ParamSource {
  public:
    /// Throws io::ConfigError naming the file when it cannot be read or has no such layout.
    explicit Ros2Params(const RosArgs &args);

    bool Get(const std::string &name, std::string &value) const override;
    bool Get(const std::string &name, bool &value) const override;
    bool Get(const std::string &name, int &value) const override;
    bool Get(const std::string &name, double &value) const override;
    bool GetNumbers(const std::string &name, std::vector<double> &values) const override;

    /// The names set that are not in `known`, each with where it was set and a "did you mean".
    [[nodiscard]] std::vector<std::string> Unknown(const std::vector<std::string> &known) const;

  private:
    template <typename T>
    bool Scalar(const std::string &name, T &value, const char *type) const;
    void Add(const std::string &prefix, const YAML::Node &node, const std::string &origin);

    struct Value {
        YAML::Node node;
        std::string origin;  ///< the file, or "-p"
    };
    std::map<std::string, Value> values_;
};

}  // namespace dorado::ros2
