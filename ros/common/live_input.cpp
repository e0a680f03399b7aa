#include "live_input.hpp"

#include <algorithm>
#include <cmath>

namespace dorado::ros_node {

bool FaultLog::Count(const std::string &cause, const std::string &detail) {
    ++recent_[cause];
    const bool first = totals_[cause]++ == 0;
    if (first) first_details_[cause] = detail;
    return first;
}

std::string FaultLog::TakeRecent() {
    std::string text;
    for (const auto &[cause, count] : recent_)
        text += (text.empty() ? "" : ", ") + cause + " " + std::to_string(count);
    recent_.clear();
    return text;
}

long long FaultLog::total() const {
    long long sum = 0;
    for (const auto &entry : totals_) sum += entry.second;
    return sum;
}

StampVerdict StampGuard::Check(int64_t stamp_ns) const {
    if (!has_last_ || stamp_ns > last_ns_) return StampVerdict::kAccept;
    return stamp_ns == last_ns_ ? StampVerdict::kDuplicate : StampVerdict::kOutOfOrder;
}

GapVerdict StampGuard::Accept(int64_t stamp_ns, bool dropped_since_last) {
    const bool first = !has_last_;
    last_interval_s_ = first ? 0.0 : static_cast<double>(stamp_ns - last_ns_) * 1e-9;
    has_last_ = true;
    last_ns_ = stamp_ns;
    if (first || dropped_since_last) return GapVerdict::kNone;
    if (last_interval_s_ > policy_.max_gap_s) return GapVerdict::kReset;
    if (ordinary_s_ > 0.0 && last_interval_s_ > policy_.report_factor * ordinary_s_)
        return GapVerdict::kIntegrate;
    ordinary_s_ = last_interval_s_;
    return GapVerdict::kNone;
}

double LatencyStats::Quantile(double q) const {
    if (samples_.empty()) return NAN;
    std::vector<double> sorted = samples_;
    std::sort(sorted.begin(), sorted.end());
    const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(sorted.size())));
    return sorted[std::min(sorted.size() - 1, rank == 0 ? 0 : rank - 1)];
}

}  // namespace dorado::ros_node
