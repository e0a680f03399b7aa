#pragma once
/// @file yaml_section.hpp
/// Strict reading of the YAML configuration files: typed reads with defaults, and errors that name
/// the file and the dotted key, so that a misspelled key never silently falls back to a default.

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "dorado/io/config_error.hpp"

namespace dorado::io {

/// Parses a YAML file; throws ConfigError "FILE: cannot open" or "FILE: not valid YAML: ...".
[[nodiscard]] YAML::Node LoadYamlFile(const std::string &path);

/// One YAML mapping of a configuration file. Remembers every key asked for, so that
/// RejectUnknownKeys() can report the keys nobody read. An absent or empty (null) mapping, and an
/// empty value, mean "the default". Every error is a ConfigError "FILE: key 'a.b.c': what".
class YamlSection {
  public:
    /// @p file names the file in errors; @p prefix is the section's dotted key ("" = top level).
    YamlSection(const YAML::Node &node, std::string file, std::string prefix = "");

    /// Throws ConfigError for @p key, relative to this section ("" = the section itself).
    [[noreturn]] void Fail(const std::string &key, const std::string &what) const;

    /// True if @p key has a (non-null) value. Marks the key as known.
    bool Has(const std::string &key);

    /// The value of @p key, or @p fallback if it has none. A wrong type fails naming the line.
    template <typename T>
    T Get(const std::string &key, const T &fallback) {
        if (!Has(key)) return fallback;
        try {
            return node_[key].template as<T>();
        } catch (const YAML::Exception &) {
            Fail(key,
                 "has the wrong type (line " + std::to_string(node_[key].Mark().line + 1) + ")");
        }
    }

    /// Overwrites @p value with the value of @p key if it has one (@p value is the default).
    template <typename T>
    void Read(const std::string &key, T &value) {
        value = Get<T>(key, value);
    }

    /// Get() that fails unless the value is a finite number > 0.
    double GetPositive(const std::string &key, double fallback);

    /// Reads a list of exactly 3 numbers into @p value (the default).
    void ReadVector3(const std::string &key, Eigen::Vector3d &value);

    /// Reads an enum given by name; fails with "must be a, b or c, got 'x'" for any other text.
    template <typename E>
    void ReadEnum(const std::string &key, E &value,
                  const std::vector<std::pair<std::string, E>> &names) {
        if (!Has(key)) return;
        const auto text = Get<std::string>(key, "");
        for (const auto &[name, e] : names) {
            if (name == text) {
                value = e;
                return;
            }
        }
        std::vector<std::string> list;
        for (const auto &entry : names) list.push_back(entry.first);
        Fail(key, "must be " + OneOf(list) + ", got '" + text + "'");
    }

    /// Reads an enum through a library's parser, which throws std::invalid_argument for bad text.
    template <typename E, typename Parse>
    void ReadParsed(const std::string &key, E &value, Parse parse) {
        if (!Has(key)) return;
        const auto text = Get<std::string>(key, "");
        try {
            value = parse(text);
        } catch (const std::invalid_argument &e) {
            Fail(key, e.what());
        }
    }

    /// The mapping under @p key (absent = all defaults). Marks the key as known.
    YamlSection Child(const std::string &key);

    /// Fails on the first key of this mapping that was never asked for, suggesting the nearest
    /// known key ("did you mean 'x'?") and listing all of them. Call after the last read.
    void RejectUnknownKeys() const;

  private:
    /// "a", "a or b", "a, b or c".
    static std::string OneOf(const std::vector<std::string> &names);

    const YAML::Node node_;  ///< const: a lookup of a missing key must not insert it
    bool present_ = false;
    std::string file_;
    std::string prefix_;
    std::set<std::string> known_;
};

}  // namespace dorado::io
