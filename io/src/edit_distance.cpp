#include "edit_distance.hpp"

#include <algorithm>

namespace dorado::io {

std::size_t EditDistance(const std::string &a, const std::string &b) {
    // One row of the distance table at a time.
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
            diagonal = up;
        }
    }
    return row[b.size()];
}

std::optional<std::string> ClosestName(const std::string &typed,
                                       const std::vector<std::string> &names,
                                       std::size_t max_edits) {
    std::optional<std::string> best;
    std::size_t best_distance = max_edits + 1;
    for (const std::string &name : names) {
        const std::size_t d = EditDistance(name, typed);
        if (d < best_distance) {
            best_distance = d;
            best = name;
        }
    }
    return best;
}

}  // namespace dorado::io
