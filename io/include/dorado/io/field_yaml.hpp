#pragma once
/// @file field_yaml.hpp
/// The visitors that read, write and list a config struct through its field list
/// (`VisitFields`, core/config_fields.hpp): the only YAML code the config structs have (the
/// odometry and mapper files, the dataset description, the simulator's sequences, the bench file).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "dorado/core/config_fields.hpp"
#include "dorado/io/yaml_section.hpp"

namespace dorado::io {

/// A value as the YAML files write it: numbers round-trip exactly in the fewest digits,
/// infinities as .inf / -.inf, vectors as [x, y, z], text quoted where YAML would misread it.
[[nodiscard]] std::string FormatValue(double value);
[[nodiscard]] std::string FormatValue(int value);
[[nodiscard]] std::string FormatValue(bool value);
[[nodiscard]] std::string FormatValue(std::int64_t value);
[[nodiscard]] std::string FormatValue(std::uint64_t value);
[[nodiscard]] std::string FormatValue(const std::string &value);
[[nodiscard]] std::string FormatValue(const std::vector<std::string> &value);
[[nodiscard]] std::string FormatValue(const Eigen::Vector3d &value);
/// {translation_m: [x, y, z], quaternion_xyzw: [x, y, z, w]}.
[[nodiscard]] std::string FormatValue(const Eigen::Isometry3d &value);
template <typename E>
[[nodiscard]] std::string FormatValue(const E &value, const Choices<E> &names) {
    for (const auto &[name, e] : names)
        if (e == value) return name;
    return "?";
}
template <typename E>
[[nodiscard]] std::string FormatValue(const std::vector<E> &values, const Choices<E> &names) {
    std::string text;
    for (const E &value : values) text += (text.empty() ? "" : ", ") + FormatValue(value, names);
    return "[" + text + "]";
}
/// An optional list: ~ (none) when absent.
template <typename E>
[[nodiscard]] std::string FormatValue(const std::optional<std::vector<E>> &values,
                                      const Choices<E> &names) {
    return values ? FormatValue(*values, names) : "~";
}
/// "doc (a | b | c)": an enum's doc with its choices.
template <typename E>
[[nodiscard]] std::string ChoicesDoc(const char *doc, const Choices<E> &names) {
    std::string choices;
    for (const auto &entry : names)
        choices += (choices.empty() ? "" : " | ") + std::string(entry.first);
    return std::string(doc) + " (" + choices + ")";
}

/// A library's Validate() error ("section.key: what", core/require.hpp) as the readers' errors
/// read: "FILE: key 'section.key': what".
[[nodiscard]] ConfigError KeyError(const std::string &file, const std::invalid_argument &e);

/// @p path (a PathField's text) relative to @p base_dir unless absolute, normalised, without a
/// trailing separator. Empty stays empty.
[[nodiscard]] std::string ResolvePath(const std::string &path, const std::string &base_dir);

/// A mount as YAML writes it: translation_m [m], and rotation_rpy_deg (Z-Y-X Euler angles [deg])
/// or quaternion_xyzw, not both. Absent keys are 0 / no rotation.
[[nodiscard]] Eigen::Isometry3d ReadTransform(YamlSection &section);

/// Reads dotted keys ("mapper.map.voxel_size_m") from a file's top-level section, each into its
/// member (absent keys keep the member, the default). RejectUnknownKeys() after the last field.
class FieldReader {
  public:
    /// @p base_dir: the folder that relative paths (PathField) are taken from.
    explicit FieldReader(YamlSection top, std::string base_dir = "")
        : top_(std::move(top)), base_dir_(std::move(base_dir)) {}

    template <typename T>
    void operator()(const char *key, T &member, const char * /*doc*/) {
        auto [section, leaf] = SectionOf(key);
        if constexpr (std::is_same_v<T, Eigen::Vector3d>) {
            section.ReadVector3(leaf, member);
        } else if constexpr (std::is_same_v<T, Eigen::Isometry3d>) {
            if (section.Has(leaf)) member = ReadTransform(Section(key));
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
    /// A list of methods: "unknown method 'x' (a, b, c)" for a name not among @p names.
    template <typename E>
    void operator()(const char *key, std::vector<E> &member, const Choices<E> &names,
                    const char * /*doc*/) {
        auto [section, leaf] = SectionOf(key);
        if (!section.Has(leaf)) return;
        std::vector<E> values;
        for (const std::string &name : section.Get<std::vector<std::string>>(leaf, {})) {
            try {
                values.push_back(ParseChoice(names, name, "method"));
            } catch (const std::invalid_argument &e) {
                section.Fail(leaf, e.what());
            }
        }
        member = std::move(values);
    }
    /// An optional list of methods: absent (or ~) is none.
    template <typename E>
    void operator()(const char *key, std::optional<std::vector<E>> &member, const Choices<E> &names,
                    const char *doc) {
        if (!Has(key)) return;
        std::vector<E> values;
        (*this)(key, values, names, doc);
        member = std::move(values);
    }
    void operator()(const char *key, std::string &member, PathField, const char * /*doc*/) {
        auto [section, leaf] = SectionOf(key);
        if (!section.Has(leaf)) return;
        const std::string written = section.Get<std::string>(leaf, "");
        member = ResolvePath(written, base_dir_);
        if (!written.empty()) paths_read_.push_back({key, written, member});
    }

    /// A path as the file wrote it and as it was resolved (for messages about a missing file).
    struct PathRead {
        std::string key;       ///< dotted, as the field list names it
        std::string written;   ///< the file's text
        std::string resolved;  ///< taken from base_dir unless absolute
    };
    /// Every non-empty path read so far, in reading order.
    [[nodiscard]] const std::vector<PathRead> &paths_read() const { return paths_read_; }
    /// The folder that the relative paths read from now on are taken from.
    void set_base_dir(std::string base_dir) { base_dir_ = std::move(base_dir); }

    /// The section that holds dotted key @p path's leaf ("" = the top level), made on first use.
    YamlSection &Section(const std::string &path);
    /// Whether dotted @p key has a (non-null) value.
    bool Has(const std::string &key);
    /// Throws ConfigError for dotted @p key: "FILE: key 'a.b': what".
    [[noreturn]] void Fail(const std::string &key, const std::string &what) {
        top_.Fail(key, what);
    }
    /// Fails on the first key that no field and no Section() asked for, deepest sections first.
    void RejectUnknownKeys();

  private:
    std::pair<YamlSection &, std::string> SectionOf(const std::string &key);

    YamlSection top_;
    std::string base_dir_;
    std::map<std::string, YamlSection> sections_;  ///< by dotted path
    std::vector<PathRead> paths_read_;
};

/// Writes the fields as YAML, each with its doc as a comment, sections opened as keys need them.
class FieldWriter {
  public:
    template <typename T>
    void operator()(const char *key, T &member, const char *doc) {
        if constexpr (std::is_same_v<T, Eigen::Isometry3d>) {
            const Eigen::Quaterniond q(member.linear());
            Add(std::string(key) + ".translation_m", FormatValue(member.translation().eval()), doc);
            Add(std::string(key) + ".quaternion_xyzw",
                "[" + FormatValue(q.x()) + ", " + FormatValue(q.y()) + ", " + FormatValue(q.z()) +
                    ", " + FormatValue(q.w()) + "]",
                "the rotation");
        } else {
            Add(key, FormatValue(member), doc);
        }
    }
    template <typename T, typename E>
    void operator()(const char *key, T &member, const Choices<E> &names, const char *doc) {
        Add(key, FormatValue(member, names), ChoicesDoc(doc, names));
    }
    void operator()(const char *key, std::string &member, PathField, const char *doc) {
        Add(key, FormatValue(member), doc);
    }
    /// A list of sections under @p key, each item the text of a FieldWriter.
    void AddList(const std::string &key, const std::vector<std::string> &items,
                 const std::string &doc);
    [[nodiscard]] const std::string &text() const { return text_; }

  private:
    void Add(const std::string &key, const std::string &value, const std::string &doc);
    /// Opens the sections of dotted @p key; returns its leaf and its depth.
    std::pair<std::string, std::size_t> Open(const std::string &key);

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
    template <typename T, typename E>
    void operator()(const char *key, T &member, const Choices<E> &names, const char *doc) {
        rows.push_back({key, FormatValue(member, names), ChoicesDoc(doc, names)});
    }
    void operator()(const char *key, std::string &member, PathField, const char *doc) {
        rows.push_back({key, FormatValue(member), doc});
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

}  // namespace dorado::io
