#pragma once
/// @file skip_log.hpp
/// The scans a command could not use, and the faults of scans it used anyway: each is counted by
/// kind, listed with its reason in summary.json, and announced on stderr as it happens: the first
/// few of each kind, then one summary line per kind (a wrong field map must not print a line per
/// scan).

#include <cstddef>
#include <cstdio>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

namespace dorado::apps {

class SkipLog {
  public:
    /// Records that scan `scan_index` was skipped; `kind` groups the counts, `reason` is the
    /// detail.
    void Add(std::size_t scan_index, const std::string &kind, const std::string &reason) {
        scans_.push_back({{"scan", scan_index}, {"reason", reason}});
        Announce(++counts_[kind], scan_index, kind, reason);
    }

    /// Records a fault in scan `scan_index` that did not stop it being used (no finite point left,
    /// a gap before it); `what` says what the command did about it.
    void Warn(std::size_t scan_index, const std::string &kind, const std::string &what) {
        warnings_.push_back({{"scan", scan_index}, {"warning", what}});
        Announce(++warning_counts_[kind], scan_index, kind, what);
    }

    /// One line per kind that had more than kPrintedPerKind scans: how many in all (the rest were
    /// counted, not printed). Call once, when the stream ends.
    void PrintSummary() const {
        for (const auto *counts : {&counts_, &warning_counts_}) {
            for (const auto &[kind, count] : *counts) {
                if (count > kPrintedPerKind)
                    std::cerr << "dorado: warning: " << kind << ": " << count
                              << " scans in all (the first " << kPrintedPerKind << " printed)\n";
            }
        }
    }

    /// Warns that scan `scan_index` has no point left (`removed_nonfinite` of them had NaN/Inf
    /// values, or it came empty); `what_was_done` says how it still got a pose.
    void WarnNoFinitePoints(std::size_t scan_index, long long removed_nonfinite,
                            const std::string &what_was_done) {
        Warn(scan_index, "no finite points",
             (removed_nonfinite > 0 ? std::to_string(removed_nonfinite) +
                                          " points with NaN/Inf values removed, none left"
                                    : std::string("no points")) +
                 what_was_done);
    }

    /// {"kind": count, ...} for summary.json's "skip_reasons".
    [[nodiscard]] nlohmann::json Counts() const { return counts_; }
    /// [{"scan": i, "reason": "..."}, ...] for summary.json's "skipped".
    [[nodiscard]] const nlohmann::json &Scans() const { return scans_; }
    /// {"kind": count, ...} for summary.json's "warnings".
    [[nodiscard]] nlohmann::json WarningCounts() const { return warning_counts_; }
    /// [{"scan": i, "warning": "..."}, ...] for summary.json's "warned".
    [[nodiscard]] const nlohmann::json &Warnings() const { return warnings_; }

    /// Scans of one kind announced on stderr one by one; the rest are summarised.
    static constexpr int kPrintedPerKind = 3;

  private:
    // The first kPrintedPerKind of a kind are printed; the next says the rest are only counted.
    static void Announce(int count, std::size_t scan_index, const std::string &kind,
                         const std::string &text) {
        if (count <= kPrintedPerKind)
            std::cerr << "dorado: warning: scan " << scan_index << ": " << text << "\n";
        else if (count == kPrintedPerKind + 1)
            std::cerr << "dorado: warning: more scans with '" << kind
                      << "' follow: counted, not printed\n";
    }

    std::map<std::string, int> counts_, warning_counts_;
    nlohmann::json scans_ = nlohmann::json::array();
    nlohmann::json warnings_ = nlohmann::json::array();
};

/// Tells a gap in the scan stream from the ordinary interval: an interval longer than kFactor
/// times the last ordinary one (`dorado info` lists gaps of 5 median intervals the same way).
class GapWatch {
  public:
    static constexpr double kFactor = 5.0;

    /// True when `dt_s` is a gap; otherwise `dt_s` becomes the ordinary interval.
    bool IsGap(double dt_s) {
        if (ordinary_s_ > 0.0 && dt_s > kFactor * ordinary_s_) return true;
        ordinary_s_ = dt_s;
        return false;
    }
    /// "10.10 s after the previous scan (ordinary interval 0.10 s)".
    [[nodiscard]] std::string Describe(double dt_s) const {
        char text[96];
        std::snprintf(text, sizeof(text),
                      "%.2f s after the previous scan (ordinary interval %.2f s)", dt_s,
                      ordinary_s_);
        return text;
    }

  private:
    double ordinary_s_ = 0.0;
};

}  // namespace dorado::apps
