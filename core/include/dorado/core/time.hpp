#pragma once
/// @file time.hpp
/// Time stamps are int64 nanoseconds everywhere; these convert at the edges.

#include <cmath>
#include <cstdint>

namespace dorado {

constexpr int64_t kNanosPerSecond = 1'000'000'000;

[[nodiscard]] constexpr double NanosToSeconds(int64_t ns) {
    return static_cast<double>(ns) * 1e-9;
}
[[nodiscard]] inline int64_t SecondsToNanos(double s) {
    return std::llround(s * 1e9);
}

}  // namespace dorado
