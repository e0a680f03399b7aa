#pragma once
/// @file closest_name.hpp
/// "Did you mean ...?": the known name nearest to a misspelled one, for the config files' unknown
/// keys and the command line's unknown options and commands.

#include <string>
#include <vector>

namespace dorado::io {

/// The name in @p known with the fewest edits (insertions, deletions, substitutions) from
/// @p name, if at most @p max_edits; the first such name on a tie; "" when none is that close.
[[nodiscard]] std::string ClosestName(const std::string &name,
                                      const std::vector<std::string> &known,
                                      std::size_t max_edits = 2);

}  // namespace dorado::io
