#pragma once
/// @file skip_log.hpp
/// The scans a command could not use: each is counted by kind, listed with its reason in
/// summary.json, and announced on stderr as it happens.

#include <cstddef>
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
        ++counts_[kind];
        scans_.push_back({{"scan", scan_index}, {"reason", reason}});
        std::cerr << "dorado: warning: scan " << scan_index << ": " << reason << "\n";
    }

    /// {"kind": count, ...} for summary.json's "skip_reasons".
    [[nodiscard]] nlohmann::json Counts() const { return counts_; }
    /// [{"scan": i, "reason": "..."}, ...] for summary.json's "skipped".
    [[nodiscard]] const nlohmann::json &Scans() const { return scans_; }

  private:
    std::map<std::string, int> counts_;
    nlohmann::json scans_ = nlohmann::json::array();
};

}  // namespace dorado::apps
