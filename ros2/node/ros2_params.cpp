#include "ros2_params.hpp"

#include <algorithm>

#include "dorado/io/closest_name.hpp"
#include "dorado/io/config_error.hpp"

namespace dorado::ros2 {
namespace {

[[noreturn]] void Fail(const std::string &name, const std::string &origin,
                       const std::string &what) {
    throw io::ConfigError("parameter '" + name + "' (" + origin + "): " + what);
}

}  // namespace

Ros2Params::Ros2Params(const RosArgs &args) {
    for (const std::string &path : args.params_files) {
        YAML::Node root;
        try {
            root = YAML::LoadFile(path);
        } catch (const YAML::Exception &e) {
            throw io::ConfigError(path + ": " + e.what());
        }
        bool found = false;
        // rcl's order: the wildcard first, then the node's own section.
        for (const std::string &key : {std::string("/**"), args.node_name, "/" + args.node_name}) {
            const YAML::Node section = root.IsMap() ? root[key] : YAML::Node();
            if (!section) continue;
            const YAML::Node params = section["ros__parameters"];
            if (!params || !params.IsMap())
                throw io::ConfigError(path + ": section '" + key +
                                      "' has no ros__parameters mapping");
            Add("", params, path);
            found = true;
        }
        if (!found)
            throw io::ConfigError(path + ": no section for node '" + args.node_name + "' ('" +
                                  args.node_name + ":' or '/**:' with ros__parameters)");
    }
    for (const auto &[name, text] : args.params) {
        try {
            values_[name] = {YAML::Load(text), "-p"};
        } catch (const YAML::Exception &e) {
            throw io::ConfigError("-p " + name + ":=" + text + ": " + e.what());
        }
    }
}

void Ros2Params::Add(const std::string &prefix, const YAML::Node &node, const std::string &origin) {
    for (const auto &entry : node) {
        const std::string name = prefix + entry.first.as<std::string>();
        if (entry.second.IsMap())
            Add(name + ".", entry.second, origin);
        else
            values_[name] = {entry.second, origin};
    }
}

template <typename T>
bool Ros2Params::Scalar(const std::string &name, T &value, const char *type) const {
    const auto it = values_.find(name);
    if (it == values_.end()) return false;
    try {
        if (!it->second.node.IsScalar()) throw YAML::Exception(YAML::Mark(), "not a scalar");
        value = it->second.node.as<T>();
    } catch (const YAML::Exception &) {
        Fail(name, it->second.origin, std::string("must be ") + type);
    }
    return true;
}

bool Ros2Params::Get(const std::string &name, std::string &value) const {
    return Scalar(name, value, "a string");
}
bool Ros2Params::Get(const std::string &name, bool &value) const {
    return Scalar(name, value, "true or false");
}
bool Ros2Params::Get(const std::string &name, int &value) const {
    return Scalar(name, value, "an integer");
}
bool Ros2Params::Get(const std::string &name, double &value) const {
    return Scalar(name, value, "a number");
}

bool Ros2Params::GetNumbers(const std::string &name, std::vector<double> &values) const {
    const auto it = values_.find(name);
    if (it == values_.end()) return false;
    const YAML::Node &node = it->second.node;
    values.clear();
    try {
        if (!node.IsSequence()) throw YAML::Exception(YAML::Mark(), "not a list");
        for (const auto &v : node) values.push_back(v.as<double>());
    } catch (const YAML::Exception &) {
        Fail(name, it->second.origin, "must be a list of numbers");
    }
    return true;
}

std::vector<std::string> Ros2Params::Unknown(const std::vector<std::string> &known) const {
    std::vector<std::string> unknown;
    for (const auto &[name, value] : values_) {
        if (std::find(known.begin(), known.end(), name) != known.end()) continue;
        const std::string closest = io::ClosestName(name, known);
        unknown.push_back("'" + name + "' (" + value.origin + ")" +
                          (closest.empty() ? "" : ", did you mean '" + closest + "'?"));
    }
    return unknown;
}

}  // namespace dorado::ros2
