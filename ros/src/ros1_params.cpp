#include "ros1_params.hpp"

#include "dorado/io/config_error.hpp"

namespace dorado::ros_node {
namespace {

[[noreturn]] void Fail(const std::string &name, const std::string &what) {
    throw io::ConfigError("parameter '" + name + "': " + what);
}

}  // namespace

const ros::NodeHandle *Ros1Params::Which(const std::string &name) const {
    if (private_.hasParam(name)) return &private_;
    if (node_.hasParam(name)) return &node_;
    return nullptr;
}

template <typename T>
bool Ros1Params::GetValue(const std::string &name, T &value) const {
    const ros::NodeHandle *handle = Which(name);
    if (!handle) return false;
    if (!handle->getParam(name, value)) Fail(name, "has the wrong type");
    return true;
}

bool Ros1Params::Get(const std::string &name, std::string &value) const {
    return GetValue(name, value);
}
bool Ros1Params::Get(const std::string &name, bool &value) const {
    return GetValue(name, value);
}
bool Ros1Params::Get(const std::string &name, int &value) const {
    return GetValue(name, value);
}
bool Ros1Params::Get(const std::string &name, double &value) const {
    return GetValue(name, value);
}

bool Ros1Params::GetNumbers(const std::string &name, std::vector<double> &values) const {
    const ros::NodeHandle *handle = Which(name);
    if (!handle) return false;
    XmlRpc::XmlRpcValue list;
    handle->getParam(name, list);
    if (list.getType() != XmlRpc::XmlRpcValue::TypeArray) Fail(name, "must be a list of numbers");
    values.clear();
    for (int i = 0; i < list.size(); ++i) {
        if (list[i].getType() == XmlRpc::XmlRpcValue::TypeDouble)
            values.push_back(static_cast<double>(list[i]));
        else if (list[i].getType() == XmlRpc::XmlRpcValue::TypeInt)
            values.push_back(static_cast<int>(list[i]));
        else
            Fail(name, "must be a list of numbers");
    }
    return true;
}

}  // namespace dorado::ros_node
