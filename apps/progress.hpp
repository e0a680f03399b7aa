#pragma once
/// @file progress.hpp
/// A one-line progress display on a terminal (stderr); silent when stderr is not a terminal.

#include <chrono>
#include <cstddef>
#include <string>

namespace dorado::apps {

class Progress {
  public:
    /// total = 0 when the total is unknown (then only counts and rate are shown).
    Progress(std::string label, std::size_t total);
    ~Progress();
    /// Sets the count of finished items and redraws at most ~10 times a second.
    void Update(std::size_t done, const std::string &status = "");
    /// Clears the line.
    void Finish();

  private:
    std::string label_;
    std::size_t total_;
    bool enabled_;
    bool finished_ = false;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point last_draw_;
};

}  // namespace dorado::apps
