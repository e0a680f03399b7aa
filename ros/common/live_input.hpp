#pragma once
/// @file live_input.hpp
/// The bookkeeping of a live scan stream, without ROS: which scans to drop (a stamp not after the
/// last one, a scan overtaken while waiting), which gaps to integrate over and which to reset
/// at, and per-cause counts that are reported in summarised warnings instead of a line per scan.

#include <chrono>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace dorado::ros_node {

/// Counts of one kind of fault, with the first message of each cause kept for the report.
class FaultLog {
  public:
    /// Counts one event of `cause`. Returns true the first time the cause is seen (the caller
    /// reports that one at once, with `detail`); later ones only go into the periodic summary.
    bool Count(const std::string &cause, const std::string &detail);

    /// "late (processing behind) 12, out of order 3" for the events since the last call, empty
    /// when there were none; the counts since the start stay in totals().
    [[nodiscard]] std::string TakeRecent();
    [[nodiscard]] const std::map<std::string, long long> &totals() const { return totals_; }
    [[nodiscard]] const std::map<std::string, std::string> &first_details() const {
        return first_details_;
    }
    [[nodiscard]] long long total() const;

  private:
    std::map<std::string, long long> totals_, recent_;
    std::map<std::string, std::string> first_details_;
};

/// What to do with a scan, from its stamp and the last accepted one.
enum class StampVerdict { kAccept, kDuplicate, kOutOfOrder };

/// What to do about the time since the last accepted scan.
enum class GapVerdict { kNone, kIntegrate, kReset };

struct GapPolicy {
    /// Above this the pipeline starts over at the last pose (a new map, no prior) [s].
    double max_gap_s = 1.0;
    /// An interval longer than this many ordinary intervals is reported (and integrated over).
    double report_factor = 5.0;
};

class StampGuard {
  public:
    explicit StampGuard(GapPolicy policy) : policy_(policy) {}

    [[nodiscard]] StampVerdict Check(int64_t stamp_ns) const;
    /// The gap before an accepted scan at stamp_ns (call after Check said kAccept); updates the
    /// ordinary interval when it is not a gap. `dropped_since_last`: the node itself dropped
    /// scans in between (late), so the sensor did not stall: never a reset, never reported.
    GapVerdict Accept(int64_t stamp_ns, bool dropped_since_last = false);
    [[nodiscard]] double last_interval_s() const { return last_interval_s_; }
    [[nodiscard]] double ordinary_interval_s() const { return ordinary_s_; }

  private:
    GapPolicy policy_;
    bool has_last_ = false;
    int64_t last_ns_ = 0;
    double ordinary_s_ = 0.0, last_interval_s_ = 0.0;
};

/// Arrival-to-publish latencies [ms]: median and 95th percentile.
class LatencyStats {
  public:
    void Add(double ms) { samples_.push_back(ms); }
    [[nodiscard]] std::size_t size() const { return samples_.size(); }
    /// The q-quantile (0..1) by the nearest rank; NaN when empty.
    [[nodiscard]] double Quantile(double q) const;

  private:
    std::vector<double> samples_;
};

}  // namespace dorado::ros_node
