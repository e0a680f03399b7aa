#include "dorado/eval/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dorado::eval {

Statistics ComputeStatistics(const std::vector<double> &values) {
    Statistics s;
    s.count = values.size();
    if (values.empty()) {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        s.rmse = s.mean = s.median = s.std = s.min = s.max = nan;
        return s;
    }
    const double n = static_cast<double>(values.size());
    double sum = 0.0;
    double sum_sq = 0.0;
    for (const double v : values) {
        sum += v;
        sum_sq += v * v;
    }
    s.mean = sum / n;
    s.rmse = std::sqrt(sum_sq / n);
    // Two-pass variance: sum_sq / n - mean^2 cancels badly when the spread is small.
    double sq_dev = 0.0;
    for (const double v : values) sq_dev += (v - s.mean) * (v - s.mean);
    s.std = std::sqrt(sq_dev / n);

    std::vector<double> sorted = values;
    std::sort(sorted.begin(), sorted.end());
    s.min = sorted.front();
    s.max = sorted.back();
    const std::size_t mid = sorted.size() / 2;
    s.median = sorted.size() % 2 == 1 ? sorted[mid] : 0.5 * (sorted[mid - 1] + sorted[mid]);
    return s;
}

}  // namespace dorado::eval
