#include "dorado/io/yaml_section.hpp"

#include <cmath>

#include "dorado/io/closest_name.hpp"

namespace dorado::io {

YAML::Node LoadYamlFile(const std::string &path) {
    try {
        return YAML::LoadFile(path);
    } catch (const YAML::BadFile &) {
        throw ConfigError(path + ": cannot open");
    } catch (const YAML::Exception &e) {
        throw ConfigError(path + ": not valid YAML: " + e.what());
    }
}

YamlSection::YamlSection(const YAML::Node &node, std::string file, std::string prefix)
    : node_(node), file_(std::move(file)), prefix_(std::move(prefix)) {
    present_ = node_.IsDefined() && !node_.IsNull();
    if (present_ && !node_.IsMap()) Fail("", "must be a mapping");
}

void YamlSection::Fail(const std::string &key, const std::string &what) const {
    std::string full = prefix_.empty() ? key : prefix_ + "." + key;
    if (key.empty()) full = prefix_.empty() ? "(top level)" : prefix_;
    throw ConfigError(file_ + ": key '" + full + "': " + what);
}

bool YamlSection::Has(const std::string &key) {
    known_.insert(key);
    return present_ && node_[key].IsDefined() && !node_[key].IsNull();
}

double YamlSection::GetPositive(const std::string &key, double fallback) {
    const double v = Get<double>(key, fallback);
    if (!(std::isfinite(v) && v > 0.0))
        Fail(key, "must be a positive number, got " + std::to_string(v));
    return v;
}

void YamlSection::ReadVector3(const std::string &key, Eigen::Vector3d &value) {
    const auto v = Get<std::vector<double>>(key, {value.x(), value.y(), value.z()});
    if (v.size() != 3) Fail(key, "must have 3 values");
    value = Eigen::Vector3d(v[0], v[1], v[2]);
}

YamlSection YamlSection::Child(const std::string &key) {
    known_.insert(key);
    return YamlSection(present_ ? node_[key] : YAML::Node(YAML::NodeType::Undefined), file_,
                       prefix_.empty() ? key : prefix_ + "." + key);
}

void YamlSection::RejectUnknownKeys() const {
    if (!present_) return;
    for (const auto &entry : node_) {
        if (!entry.first.IsScalar())
            Fail("", "has a key that is not text (line " +
                         std::to_string(entry.first.Mark().line + 1) + ")");
        const std::string &key = entry.first.Scalar();
        if (known_.count(key)) continue;
        const std::string closest =
            ClosestName(key, std::vector<std::string>(known_.begin(), known_.end()));
        const std::string hint = closest.empty() ? "" : " (did you mean '" + closest + "'?)";
        std::string list;
        for (const auto &k : known_) list += (list.empty() ? "" : ", ") + k;
        Fail(key, "unknown key" + hint + "; known keys: " + list);
    }
}

std::string YamlSection::OneOf(const std::vector<std::string> &names) {
    std::string list;
    for (std::size_t i = 0; i < names.size(); ++i) {
        if (i > 0) list += i + 1 == names.size() ? " or " : ", ";
        list += names[i];
    }
    return list;
}

}  // namespace dorado::io
