#include "progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace dorado::apps {

Progress::Progress(std::string label, std::size_t total)
    : label_(std::move(label)),
      total_(total),
      enabled_(isatty(fileno(stderr)) != 0),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_ - std::chrono::seconds(1)) {}

Progress::~Progress() {
    Finish();
}

void Progress::Update(std::size_t done, const std::string &status) {
    if (!enabled_ || finished_) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_draw_ < std::chrono::milliseconds(100) && done != total_) return;
    last_draw_ = now;
    const double elapsed_s = std::chrono::duration<double>(now - start_).count();
    const double rate = elapsed_s > 0.0 ? static_cast<double>(done) / elapsed_s : 0.0;
    if (total_ > 0) {
        constexpr int kWidth = 30;
        const double fraction = static_cast<double>(done) / static_cast<double>(total_);
        const int filled = static_cast<int>(fraction * kWidth);
        std::string bar(static_cast<std::size_t>(filled), '#');
        bar.resize(kWidth, '.');
        const double eta_s = rate > 0.0 ? static_cast<double>(total_ - done) / rate : 0.0;
        std::fprintf(stderr, "\r%s [%s] %zu/%zu %5.1f/s eta %4.0fs %s\033[K", label_.c_str(),
                     bar.c_str(), done, total_, rate, eta_s, status.c_str());
    } else {
        std::fprintf(stderr, "\r%s %zu done %5.1f/s %s\033[K", label_.c_str(), done, rate,
                     status.c_str());
    }
    std::fflush(stderr);
}

void Progress::Finish() {
    if (!enabled_ || finished_) return;
    finished_ = true;
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
}

}  // namespace dorado::apps
