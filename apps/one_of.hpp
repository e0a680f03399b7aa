#pragma once
/// @file one_of.hpp
/// A command-line value that must be one of a few names (`config print mapper`, `calibrate sx`):
/// a misspelt one is refused with the names allowed and the closest of them.

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "dorado/io/closest_name.hpp"

namespace dorado::apps {

/// "'mapperr' is not one of odometry, mapper (did you mean 'mapper'?)" for a value not in @p names.
inline CLI::Validator OneOf(const std::vector<std::string> &names) {
    std::string list;
    for (const auto &name : names) list += (list.empty() ? "" : ", ") + name;
    return CLI::Validator(
        [names, list](std::string &value) -> std::string {
            for (const auto &name : names)
                if (value == name) return "";
            const std::string closest = io::ClosestName(value, names);
            return "'" + value + "' is not one of " + list +
                   (closest.empty() ? "" : " (did you mean '" + closest + "'?)");
        },
        "{" + list + "}");
}

}  // namespace dorado::apps
