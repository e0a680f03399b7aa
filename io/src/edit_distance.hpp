#pragma once
// Private to dorado_io: how far a name typed is from the names that exist, for "did you mean".

#include <optional>
#include <string>
#include <vector>

namespace dorado::io {

/// Levenshtein distance: insertions, deletions and substitutions.
[[nodiscard]] std::size_t EditDistance(const std::string &a, const std::string &b);

/// The name of @p names nearest to @p typed, if one is at most @p max_edits edits away.
[[nodiscard]] std::optional<std::string> ClosestName(const std::string &typed,
                                                     const std::vector<std::string> &names,
                                                     std::size_t max_edits);

}  // namespace dorado::io
