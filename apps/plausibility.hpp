#pragma once
/// @file plausibility.hpp
/// Results that cannot be right end with a warning and a non-zero exit (kImplausibleExit) after
/// they are written, unless the user passes --accept-implausible: most scans falling back, a path
/// far shorter than the Doppler speed integrates to, Doppler values beyond what the radar can
/// measure (a wrong field or column read as the Doppler).

#include <CLI/CLI.hpp>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "dorado/core/radar_scan.hpp"

namespace dorado::apps {

/// The exit code of a run whose results were written but are implausible.
inline constexpr int kImplausibleExit = 3;

/// The limits of plausibility (each documented in docs/outputs.md).
struct PlausibilityLimits {
    double max_fallback_fraction = 0.5;  ///< of the scans used
    /// The path may be this much shorter than the Doppler distance, when that is long enough.
    double min_path_to_doppler_distance = 0.5;
    double min_doppler_distance_m = 5.0;
    /// Without radar.doppler_unambiguous_mps: no road or robot radar measures faster.
    double max_doppler_mps = 100.0;
    double max_fraction_beyond = 0.01;  ///< of the points
    double max_gap_s = 1.0;             ///< longer steps between scans add no Doppler distance
};

/// Tallies a run's scans; Problems() judges them.
class PlausibilityWatch {
  public:
    /// @p doppler_unambiguous_mps: the radar's (0: unknown; limits.max_doppler_mps is used).
    explicit PlausibilityWatch(double doppler_unambiguous_mps, PlausibilityLimits limits = {});

    /// A scan as read: its Doppler values against the radar's range.
    void AddPoints(const RadarScan &scan);
    /// A scan's radar speed (|v_radar| of a valid ego-velocity) at its stamp: the distance the
    /// Doppler integrates to.
    void AddSpeed(int64_t stamp_ns, bool valid, double speed_mps);

    /// One sentence per implausible finding (empty: plausible). @p fallback_what names what a
    /// fallback is ("fell back to the prior"); a negative @p path_length_m: a run that does not
    /// translate (odometry --method imu), no path check.
    [[nodiscard]] std::vector<std::string> Problems(std::size_t scans_used, std::size_t fallbacks,
                                                    const std::string &fallback_what,
                                                    double path_length_m) const;
    [[nodiscard]] double doppler_distance_m() const { return doppler_distance_m_; }

  private:
    PlausibilityLimits limits_;
    double doppler_limit_mps_;
    bool limit_is_radars_;
    long long points_ = 0, beyond_ = 0;
    double min_doppler_ = 0.0, max_doppler_ = 0.0;
    double doppler_distance_m_ = 0.0;
    bool has_last_ = false;
    int64_t last_ns_ = 0;
};

/// summary.json's record: {"implausible": [...], "doppler_distance_m": ...}.
[[nodiscard]] nlohmann::json PlausibilityRecord(const std::vector<std::string> &problems,
                                                const PlausibilityWatch &watch, bool accepted);

/// After the results are written: each problem on stderr; then, unless @p accepted
/// (--accept-implausible), throws StoppedEarly with kImplausibleExit.
void EndIfImplausible(const std::vector<std::string> &problems, const std::string &command,
                      const std::string &out_dir, bool accepted);

/// --accept-implausible on a command that judges its results.
inline void AddAcceptImplausibleFlag(CLI::App *cmd, bool &accepted) {
    cmd->add_flag("--accept-implausible", accepted,
                  "exit 0 although the results look implausible (most scans falling back, a "
                  "path far shorter than the Doppler speed integrates to, Doppler values beyond "
                  "the radar's range); without it such a run exits 3 after writing its outputs");
}

}  // namespace dorado::apps
