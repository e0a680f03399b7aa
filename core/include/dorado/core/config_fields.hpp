#pragma once
/// @file config_fields.hpp
/// The protocol of the config structs' field lists (`VisitFields(Config &, Visitor &&)` next to
/// each struct): every configurable member is listed ONCE, with its key and a one-line doc, and
/// the YAML reader, the writer (`dorado config print`), the docs' key tables and the tests that
/// the shipped configs/*.yaml equal the built-in defaults all walk that one list. No YAML here.
///
/// A visitor is any callable with these overloads (a visitor need only have those that the field
/// lists it walks use):
///   v(const char *key, T &member, const char *doc)                 T: bool, int, double, int64_t,
///                                   uint64_t, std::string, std::vector<std::string>,
///                                   Eigen::Vector3d, Eigen::Isometry3d (a mount: translation_m
///                                   and a rotation, a section of its own in YAML)
///   v(const char *key, E &member, const Choices<E> &names, const char *doc)   E: an enum
///   v(const char *key, std::vector<E> &member, const Choices<E> &names, const char *doc)
///                                   a list of methods (E: an enum; the bench's method lists)
///   v(const char *key, std::optional<std::vector<E>> &member, const Choices<E> &names, doc)
///                                   an optional one (absent: none)
///   v(const char *key, std::string &member, PathField, const char *doc)
///                                   a file or folder: relative to the file that names it
/// `key` is dotted relative to the struct ("map.voxel_size_m"); a struct that holds another
/// struct's fields under a section passes Prefixed{"section.", v} to that struct's VisitFields.

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace dorado {

/// The one spelling of each value of a config enum, in the order the docs list them.
template <typename E>
using Choices = std::vector<std::pair<const char *, E>>;

/// The enum value spelled @p text; throws std::invalid_argument "unknown <what> '<text>' (a, b, c)"
/// listing the choices.
template <typename E>
[[nodiscard]] E ParseChoice(const Choices<E> &choices, const std::string &text,
                            const std::string &what) {
    std::string names;
    for (const auto &[name, value] : choices) {
        if (text == name) return value;
        names += (names.empty() ? "" : ", ") + std::string(name);
    }
    throw std::invalid_argument("unknown " + what + " '" + text + "' (" + names + ")");
}

/// The third argument of a path field: a file or folder the YAML file names, read relative to that
/// file's folder and normalised ("data/./seq/" is "data/seq": no trailing separator, so that
/// parent_path() is the folder above).
struct PathField {};
inline constexpr PathField kPath{};

/// A visitor that forwards to another with "prefix" prepended to every key.
template <typename Visitor>
struct Prefixed {
    const char *prefix;
    Visitor &visitor;

    template <typename T>
    void operator()(const char *key, T &member, const char *doc) const {
        const std::string full = std::string(prefix) + key;
        visitor(full.c_str(), member, doc);
    }
    /// An enum, a list of methods or a path: forwarded with its third argument.
    template <typename T, typename Extra>
    void operator()(const char *key, T &member, const Extra &extra, const char *doc) const {
        const std::string full = std::string(prefix) + key;
        visitor(full.c_str(), member, extra, doc);
    }
};

template <typename Visitor>
Prefixed(const char *, Visitor &) -> Prefixed<Visitor>;

}  // namespace dorado
