#include "dorado/config/field_yaml.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace dorado::config {

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
std::string FormatValue(std::uint64_t value) {
    return std::to_string(value);
}
std::string FormatValue(const Eigen::Vector3d &value) {
    return "[" + FormatValue(value.x()) + ", " + FormatValue(value.y()) + ", " +
           FormatValue(value.z()) + "]";
}

io::ConfigError KeyError(const std::string &file, const std::invalid_argument &e) {
    const std::string what = e.what();
    const auto colon = what.find(": ");
    if (colon == std::string::npos || what.find(' ') < colon)
        return io::ConfigError(file + ": " + what);
    return io::ConfigError(file + ": key '" + what.substr(0, colon) + "'" + what.substr(colon));
}

io::YamlSection &FieldReader::Section(const std::string &path) {
    if (path.empty()) return top_;
    const auto found = sections_.find(path);
    if (found != sections_.end()) return found->second;
    const auto dot = path.rfind('.');
    io::YamlSection &parent = dot == std::string::npos ? top_ : Section(path.substr(0, dot));
    io::YamlSection child = parent.Child(dot == std::string::npos ? path : path.substr(dot + 1));
    return sections_.emplace(path, std::move(child)).first->second;
}

std::pair<io::YamlSection &, std::string> FieldReader::SectionOf(const std::string &key) {
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
    text_ += std::string(2 * path.size(), ' ') + leaf + ": " + value + "  # " + doc + "\n";
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

}  // namespace dorado::config
