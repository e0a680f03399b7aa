#include "dorado/io/field_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"

namespace dorado::io {

std::string FormatValue(double value) {
    if (std::isinf(value)) return value > 0 ? ".inf" : "-.inf";
    if (std::isnan(value)) return ".nan";
    // The fewest digits that read back exactly: fixed notation for ordinary magnitudes (100.0,
    // 0.003), the shortest %g otherwise.
    char buffer[64];
    const double magnitude = std::abs(value);
    bool found = false;
    if (magnitude == 0.0 || (magnitude >= 1e-4 && magnitude < 1e15)) {
        for (int decimals = 0; decimals <= 17 && !found; ++decimals) {
            std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
            found = std::strtod(buffer, nullptr) == value;
        }
    }
    for (int digits = 1; digits <= 17 && !found; ++digits) {
        std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
        found = std::strtod(buffer, nullptr) == value;
    }
    std::string text = buffer;
    // YAML reads "1" as an integer, which is fine for a double member, but keep a double a double.
    if (text.find_first_of(".eEn") == std::string::npos) text += ".0";
    return text;
}

std::string FormatValue(int value) {
    return std::to_string(value);
}
std::string FormatValue(bool value) {
    return value ? "true" : "false";
}
std::string FormatValue(std::int64_t value) {
    return std::to_string(value);
}
std::string FormatValue(std::uint64_t value) {
    return std::to_string(value);
}
std::string FormatValue(const std::string &value) {
    YAML::Emitter out;
    out << value;
    return out.c_str();
}
std::string FormatValue(const std::vector<std::string> &value) {
    YAML::Emitter out;
    out << YAML::Flow << value;
    return out.c_str();
}
std::string FormatValue(const Eigen::Vector3d &value) {
    return "[" + FormatValue(value.x()) + ", " + FormatValue(value.y()) + ", " +
           FormatValue(value.z()) + "]";
}

std::string FormatValue(const Eigen::Isometry3d &value) {
    const Eigen::Quaterniond q(value.linear());
    return "{translation_m: " + FormatValue(Eigen::Vector3d(value.translation())) +
           ", quaternion_xyzw: [" + FormatValue(q.x()) + ", " + FormatValue(q.y()) + ", " +
           FormatValue(q.z()) + ", " + FormatValue(q.w()) + "]}";
}

ConfigError KeyError(const std::string &file, const std::invalid_argument &e) {
    const std::string what = e.what();
    const auto colon = what.find(": ");
    if (colon == std::string::npos || what.find(' ') < colon)
        return ConfigError(file + ": " + what);
    return ConfigError(file + ": key '" + what.substr(0, colon) + "'" + what.substr(colon));
}

std::string ResolvePath(const std::string &path, const std::string &base_dir) {
    namespace fs = std::filesystem;
    if (path.empty()) return path;
    fs::path resolved = fs::path(path).is_absolute() || base_dir.empty()
                            ? fs::path(path)
                            : fs::path(base_dir) / path;
    resolved = resolved.lexically_normal();
    // "data/sequence_105/" is "data/sequence_105": its parent_path() is "data", not itself.
    while (!resolved.has_filename() && resolved.has_relative_path())
        resolved = resolved.parent_path();
    return resolved.string();
}

Eigen::Isometry3d ReadTransform(YamlSection &section) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    section.ReadVector3("translation_m", t);
    T.translation() = t;
    const bool has_rpy = section.Has("rotation_rpy_deg");
    const bool has_q = section.Has("quaternion_xyzw");
    if (has_rpy && has_q)
        section.Fail("rotation_rpy_deg",
                     "give either rotation_rpy_deg or quaternion_xyzw, not both");
    if (has_rpy) {
        Eigen::Vector3d rpy = Eigen::Vector3d::Zero();
        section.ReadVector3("rotation_rpy_deg", rpy);
        T.linear() = RotationFromRollPitchYaw(DegToRad(rpy));
    }
    if (has_q) {
        const auto q = section.Get<std::vector<double>>("quaternion_xyzw", {});
        if (q.size() != 4) section.Fail("quaternion_xyzw", "must have 4 values");
        const Eigen::Quaterniond quat(q[3], q[0], q[1], q[2]);
        if (std::abs(quat.norm() - 1.0) > 1e-3) section.Fail("quaternion_xyzw", "must have norm 1");
        T.linear() = quat.normalized().toRotationMatrix();
    }
    if (!T.matrix().allFinite()) section.Fail("", "is not finite");
    return T;
}

YamlSection &FieldReader::Section(const std::string &path) {
    if (path.empty()) return top_;
    const auto found = sections_.find(path);
    if (found != sections_.end()) return found->second;
    const auto dot = path.rfind('.');
    YamlSection &parent = dot == std::string::npos ? top_ : Section(path.substr(0, dot));
    YamlSection child = parent.Child(dot == std::string::npos ? path : path.substr(dot + 1));
    return sections_.emplace(path, std::move(child)).first->second;
}

bool FieldReader::Has(const std::string &key) {
    auto [section, leaf] = SectionOf(key);
    return section.Has(leaf);
}

std::pair<YamlSection &, std::string> FieldReader::SectionOf(const std::string &key) {
    const auto dot = key.rfind('.');
    if (dot == std::string::npos) return {top_, key};
    return {Section(key.substr(0, dot)), key.substr(dot + 1)};
}

void FieldReader::RejectUnknownKeys() {
    // std::map orders "a" before "a.b": walk backwards so that children are checked first.
    for (auto it = sections_.rbegin(); it != sections_.rend(); ++it) it->second.RejectUnknownKeys();
    top_.RejectUnknownKeys();
}

void FieldWriter::Add(const std::string &key, const std::string &value, const std::string &doc) {
    const auto [leaf, depth] = Open(key);
    text_ += std::string(2 * depth, ' ') + leaf + ": " + value + "  # " + doc + "\n";
}

void FieldWriter::AddList(const std::string &key, const std::vector<std::string> &items,
                          const std::string &doc) {
    const auto [leaf, depth] = Open(key);
    const std::string indent(2 * depth, ' ');
    text_ += indent + leaf + ":  # " + doc + "\n";
    for (const std::string &item : items) {
        bool first = true;
        std::size_t start = 0;
        for (std::size_t end = item.find('\n'); end != std::string::npos;
             start = end + 1, end = item.find('\n', start)) {
            text_ += indent + (first ? "  - " : "    ") + item.substr(start, end - start) + "\n";
            first = false;
        }
    }
}

std::pair<std::string, std::size_t> FieldWriter::Open(const std::string &key) {
    std::vector<std::string> path;
    std::size_t start = 0;
    for (std::size_t dot = key.find('.'); dot != std::string::npos; dot = key.find('.', start)) {
        path.push_back(key.substr(start, dot - start));
        start = dot + 1;
    }
    const std::string leaf = key.substr(start);
    std::size_t same = 0;
    while (same < path.size() && same < open_.size() && path[same] == open_[same]) ++same;
    for (std::size_t depth = same; depth < path.size(); ++depth)
        text_ += std::string(2 * depth, ' ') + path[depth] + ":\n";
    open_ = path;
    return {leaf, path.size()};
}

std::string MarkdownTable(const std::vector<FieldRow> &rows) {
    std::string text = "| key | default | meaning |\n|---|---|---|\n";
    for (const auto &row : rows) {
        std::string doc;
        for (const char c : row.doc) doc += c == '|' ? std::string("\\|") : std::string(1, c);
        text += "| `" + row.key + "` | `" + row.value + "` | " + doc + " |\n";
    }
    return text;
}

}  // namespace dorado::io
