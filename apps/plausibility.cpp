#include "plausibility.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "dorado/core/time.hpp"
#include "stream_guard.hpp"

namespace dorado::apps {

namespace {

std::string Fixed(double v, int digits) {
    char text[64];
    std::snprintf(text, sizeof(text), "%.*f", digits, v);
    return text;
}

}  // namespace

PlausibilityWatch::PlausibilityWatch(double doppler_unambiguous_mps, PlausibilityLimits limits)
    : limits_(limits),
      doppler_limit_mps_(doppler_unambiguous_mps > 0.0 ? doppler_unambiguous_mps
                                                       : limits.max_doppler_mps),
      limit_is_radars_(doppler_unambiguous_mps > 0.0) {}

void PlausibilityWatch::AddPoints(const RadarScan &scan) {
    for (Eigen::Index i = 0; i < scan.doppler_mps.size(); ++i) {
        const double d = scan.doppler_mps[i];
        if (!std::isfinite(d)) continue;
        if (points_ == 0) min_doppler_ = max_doppler_ = d;
        min_doppler_ = std::min(min_doppler_, d);
        max_doppler_ = std::max(max_doppler_, d);
        ++points_;
        // The radar wraps into [-v, v): a value beyond it was not measured as a Doppler.
        beyond_ += std::abs(d) > doppler_limit_mps_ * (1.0 + 1e-6);
    }
}

void PlausibilityWatch::AddSpeed(int64_t stamp_ns, bool valid, double speed_mps) {
    if (has_last_ && valid && std::isfinite(speed_mps)) {
        const double dt = NanosToSeconds(stamp_ns - last_ns_);
        if (dt > 0.0 && dt <= limits_.max_gap_s) doppler_distance_m_ += speed_mps * dt;
    }
    has_last_ = true;
    last_ns_ = stamp_ns;
}

std::vector<std::string> PlausibilityWatch::Problems(std::size_t scans_used, std::size_t fallbacks,
                                                     const std::string &fallback_what,
                                                     double path_length_m) const {
    std::vector<std::string> problems;
    if (scans_used > 0 && static_cast<double>(fallbacks) >
                              limits_.max_fallback_fraction * static_cast<double>(scans_used))
        problems.push_back(std::to_string(fallbacks) + " of " + std::to_string(scans_used) +
                           " scans " + fallback_what +
                           " (more than half: the fields, the mount or the settings do not fit "
                           "this recording)");
    if (path_length_m >= 0.0 && doppler_distance_m_ >= limits_.min_doppler_distance_m &&
        path_length_m < limits_.min_path_to_doppler_distance * doppler_distance_m_)
        problems.push_back("the path is " + Fixed(path_length_m, 1) +
                           " m long but the Doppler speed integrates to " +
                           Fixed(doppler_distance_m_, 1) +
                           " m (check the mount, extrinsics.T_base_radar, and the vehicle model)");
    if (points_ > 0 &&
        static_cast<double>(beyond_) > limits_.max_fraction_beyond * static_cast<double>(points_))
        problems.push_back(std::to_string(beyond_) + " of " + std::to_string(points_) +
                           " points have a Doppler " + "beyond +-" + Fixed(doppler_limit_mps_, 1) +
                           " m/s (" +
                           (limit_is_radars_ ? std::string("radar.doppler_unambiguous_mps")
                                             : "faster than any vehicle radar measures") +
                           "; read " + Fixed(min_doppler_, 1) + ".." + Fixed(max_doppler_, 1) +
                           " m/s: check fields.doppler and folder.columns)");
    return problems;
}

nlohmann::json PlausibilityRecord(const std::vector<std::string> &problems,
                                  const PlausibilityWatch &watch, bool accepted) {
    return {{"implausible", problems},
            {"implausible_accepted", accepted && !problems.empty()},
            {"doppler_distance_m", watch.doppler_distance_m()}};
}

void EndIfImplausible(const std::vector<std::string> &problems, const std::string &command,
                      const std::string &out_dir, bool accepted) {
    for (const std::string &problem : problems)
        std::fprintf(stderr, "%s: warning: implausible: %s\n", command.c_str(), problem.c_str());
    if (problems.empty() || accepted) return;
    throw StoppedEarly(command + ": the results in " + out_dir + " are implausible (" +
                           std::to_string(problems.size()) +
                           " warnings above); --accept-implausible keeps them with exit 0",
                       kImplausibleExit);
}

}  // namespace dorado::apps
