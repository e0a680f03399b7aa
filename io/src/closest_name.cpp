#include "dorado/io/closest_name.hpp"

#include <algorithm>

namespace dorado::io {

namespace {

/// Levenshtein distance: insertions, deletions and substitutions, one row at a time.
std::size_t EditDistance(const std::string &a, const std::string &b) {
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

}  // namespace

std::string ClosestName(const std::string &name, const std::vector<std::string> &known,
                        std::size_t max_edits) {
    std::string closest;
    std::size_t best = max_edits + 1;
    for (const auto &k : known) {
        const std::size_t d = EditDistance(k, name);
        if (d < best) {
            best = d;
            closest = k;
        }
    }
    return closest;
}

}  // namespace dorado::io
