#pragma once
/// @file field_yaml.hpp
/// The visitors that read, write and list a config struct through its field list
/// (`VisitFields`, core/config_fields.hpp): the only YAML code the config structs have.

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "dorado/core/config_fields.hpp"
#include "dorado/io/yaml_section.hpp"

namespace dorado::config {

/// A value as the YAML files write it: numbers round-trip exactly in the fewest digits,
/// infinities as .inf / -.inf, vectors as [x, y, z].
[[nodiscard]] std::string FormatValue(double value);
[[nodiscard]] std::string FormatValue(int value);
[[nodiscard]] std::string FormatValue(bool value);
[[nodiscard]] std::string FormatValue(std::uint64_t value);
[[nodiscard]] std::string FormatValue(const Eigen::Vector3d &value);
template <typename E>
[[nodiscard]] std::string FormatValue(const E &value, const Choices<E> &names) {
    for (const auto &[name, e] : names)
        if (e == value) return name;
    return "?";
}

/// A library's Validate() error ("section.key: what", core/require.hpp) as the readers' errors
/// read: "FILE: key 'section.key': what".
[[nodiscard]] io::ConfigError KeyError(const std::string &file, const std::invalid_argument &e);

/// Reads dotted keys ("mapper.map.voxel_size_m") from a file's top-level section, each into its
/// member (absent keys keep the member, the default). RejectUnknownKeys() after the last field.
class FieldReader {
  public:
    explicit FieldReader(io::YamlSection top) : top_(std::move(top)) {}

    template <typename T>
    void operator()(const char *key, T &member, const char * /*doc*/) {
        auto [section, leaf] = SectionOf(key);
        if constexpr (std::is_same_v<T, Eigen::Vector3d>) {
            section.ReadVector3(leaf, member);
        } else {
            section.Read(leaf, member);
        }
    }
    template <typename E>
    void operator()(const char *key, E &member, const Choices<E> &names, const char * /*doc*/) {
        auto [section, leaf] = SectionOf(key);
        std::vector<std::pair<std::string, E>> list(names.begin(), names.end());
        section.ReadEnum(leaf, member, list);
    }

    /// The section that holds dotted key @p path's leaf ("" = the top level), made on first use.
    io::YamlSection &Section(const std::string &path);
    /// Fails on the first key that no field and no Section() asked for, deepest sections first.
    void RejectUnknownKeys();

  private:
    std::pair<io::YamlSection &, std::string> SectionOf(const std::string &key);

    io::YamlSection top_;
    std::map<std::string, io::YamlSection> sections_;  ///< by dotted path
};

/// Writes the fields as YAML, each with its doc as a comment, sections opened as keys need them.
class FieldWriter {
  public:
    template <typename T>
    void operator()(const char *key, T &member, const char *doc) {
        Add(key, FormatValue(member), doc);
    }
    template <typename E>
    void operator()(const char *key, E &member, const Choices<E> &names, const char *doc) {
        std::string choices;
        for (const auto &entry : names)
            choices += (choices.empty() ? "" : " | ") + std::string(entry.first);
        Add(key, FormatValue(member, names), std::string(doc) + " (" + choices + ")");
    }
    [[nodiscard]] const std::string &text() const { return text_; }

  private:
    void Add(const std::string &key, const std::string &value, const std::string &doc);

    std::string text_;
    std::vector<std::string> open_;  ///< the sections the last key was in
};

/// One row per field: dotted key, default (as FormatValue writes it), doc.
struct FieldRow {
    std::string key;
    std::string value;
    std::string doc;
};
class FieldLister {
  public:
    template <typename T>
    void operator()(const char *key, T &member, const char *doc) {
        rows.push_back({key, FormatValue(member), doc});
    }
    template <typename E>
    void operator()(const char *key, E &member, const Choices<E> &names, const char *doc) {
        std::string choices;
        for (const auto &entry : names)
            choices += (choices.empty() ? "" : " | ") + std::string(entry.first);
        rows.push_back({key, FormatValue(member, names), std::string(doc) + " (" + choices + ")"});
    }
    std::vector<FieldRow> rows;
};

/// The rows of @p config's fields, each key prefixed with @p prefix.
template <typename Config>
[[nodiscard]] std::vector<FieldRow> ListFields(Config config, const char *prefix = "") {
    FieldLister lister;
    VisitFields(config, Prefixed{prefix, lister});
    return lister.rows;
}

/// A markdown table (| key | default | meaning |) of @p rows.
[[nodiscard]] std::string MarkdownTable(const std::vector<FieldRow> &rows);

}  // namespace dorado::config
