#pragma once
/// @file time.hpp
/// Time stamps are int64 nanoseconds everywhere; these convert at the edges.

#include <chrono>
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

/// The clock of every wall-time measurement (stage timings, latencies, run times).
using Clock = std::chrono::steady_clock;

/// Wall time since @p start [ms]: the per-stage timings of the mapper, the front end and the node.
[[nodiscard]] inline double MillisecondsSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace dorado
