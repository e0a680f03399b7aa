#pragma once
/// @file statistics.hpp
/// Summary statistics of an error series, with evo's definitions (population std, median of the
/// two middle values for an even count).

#include <cstddef>
#include <vector>

namespace dorado::eval {

struct Statistics {
    double rmse = 0.0;
    double mean = 0.0;
    double median = 0.0;
    double std = 0.0;  ///< population standard deviation (numpy's np.std, as evo)
    double min = 0.0;
    double max = 0.0;
    std::size_t count = 0;
};

/// Statistics of `values`; all fields are NaN and count is 0 for an empty series.
[[nodiscard]] Statistics ComputeStatistics(const std::vector<double> &values);

}  // namespace dorado::eval
