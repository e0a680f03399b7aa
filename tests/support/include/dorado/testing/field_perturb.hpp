#pragma once
/// @file field_perturb.hpp
/// A field-list visitor for the tests that every key reads back: sets each field to a value other
/// than its own (a test then mends the few that a reader's checks refuse).

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "dorado/core/config_fields.hpp"

namespace dorado::testing {

struct Perturb {
    std::string path_root = "/perturbed";  ///< paths become absolute, under this folder

    void operator()(const char *, double &x, const char *) const {
        x = std::isinf(x) ? -100.0 : (x == 0.0 || std::isnan(x)) ? 0.25 : 0.75 * x;
    }
    void operator()(const char *, int &x, const char *) const { x += 1; }
    void operator()(const char *, std::int64_t &x, const char *) const { x += 1; }
    void operator()(const char *, std::uint64_t &x, const char *) const { x += 1; }
    void operator()(const char *, bool &x, const char *) const { x = !x; }
    void operator()(const char *key, std::string &x, const char *) const {
        x += std::string("_") + key;
    }
    void operator()(const char *key, std::vector<std::string> &x, const char *) const {
        x.push_back(key);
    }
    void operator()(const char *key, Eigen::Vector3d &x, const char *doc) const {
        for (int i = 0; i < 3; ++i) (*this)(key, x[i], doc);
    }
    /// Half a turn about x (a quaternion that writes exactly) and a shift.
    void operator()(const char *, Eigen::Isometry3d &x, const char *) const {
        x.linear() = x.linear() * Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();
        x.translation() += Eigen::Vector3d(0.5, -0.25, 0.125);
    }
    void operator()(const char *key, std::string &x, PathField, const char *) const {
        x = path_root + "/" + key;
    }
    template <typename E>
    void operator()(const char *, E &x, const Choices<E> &names, const char *) const {
        for (std::size_t i = 0; i < names.size(); ++i) {
            if (names[i].second == x) {
                x = names[(i + 1) % names.size()].second;
                return;
            }
        }
    }
    /// A list of methods: the last one only (or all, when it was that).
    template <typename E>
    void operator()(const char *, std::vector<E> &x, const Choices<E> &names, const char *) const {
        const std::vector<E> last{names.back().second};
        if (x == last) {
            x.clear();
            for (const auto &entry : names) x.push_back(entry.second);
        } else {
            x = last;
        }
    }
    /// An optional list: the first method only.
    template <typename E>
    void operator()(const char *, std::optional<std::vector<E>> &x, const Choices<E> &names,
                    const char *) const {
        x = std::vector<E>{names.front().second};
    }
};

}  // namespace dorado::testing
