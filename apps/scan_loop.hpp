#pragma once
/// @file scan_loop.hpp
/// A dataset's event stream through the front end, with the bookkeeping `dorado odometry` and
/// `dorado map` both report: unreadable and out-of-order scans (skipped, counted), scans without
/// a finite point and gaps (used, warned), NaN/Inf points removed.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "dorado/frontend/radar_front_end.hpp"
#include "dorado/io/dataset.hpp"
#include "progress.hpp"
#include "skip_log.hpp"
#include "stream_guard.hpp"

namespace dorado::apps {

class ScanLoop {
  public:
    using OnScan =
        std::function<void(const io::DatasetEvent &event, const frontend::FrontEndResult &result)>;

    explicit ScanLoop(frontend::RadarFrontEnd &front_end) : front_end_(front_end) {}

    /// Reads events until the stream ends (or the guard stops it): IMU samples go to the front
    /// end, radar scans through it; on_scan is called for every scan it accepted.
    void Run(io::DatasetReader &reader, StreamGuard &guard, Progress &progress,
             const OnScan &on_scan);

    [[nodiscard]] const SkipLog &skips() const { return skips_; }
    [[nodiscard]] std::size_t scans() const { return scans_; }  ///< radar messages, read or not
    [[nodiscard]] std::size_t used() const { return used_; }    ///< accepted by the front end
    [[nodiscard]] long long nonfinite_points() const { return nonfinite_points_; }
    /// Some scan went through the planar (2D radar) chain.
    [[nodiscard]] bool planar() const { return planar_; }

  private:
    void Warn(const io::DatasetEvent &event, const frontend::FrontEndResult &result);

    frontend::RadarFrontEnd &front_end_;
    SkipLog skips_;
    GapWatch gaps_;
    std::size_t scans_ = 0, used_ = 0;
    long long nonfinite_points_ = 0;
    bool planar_ = false;
};

/// Whether the dataset names an IMU: a recording's imu topic, or an IMU file (`imu.path`).
[[nodiscard]] bool HasImu(const io::DatasetConfig &dataset);
/// The key that names (or would name) the dataset's IMU: rosbag.imu_topic or imu.path.
[[nodiscard]] const char *ImuKey(const io::DatasetConfig &dataset);
/// Where the IMU samples come from, for messages: "FILE (rosbag.imu_topic TOPIC)" or "FILE
/// (imu.path)".
[[nodiscard]] std::string ImuSource(const io::DatasetConfig &dataset);
/// The file to name in a message about the dataset description (the YAML, or the bag given).
[[nodiscard]] std::string DatasetFile(const io::DatasetConfig &dataset, const std::string &arg);
/// With several radars listed (`radars:`), says once on stderr which one `command` reads (the
/// `folder:` + `extrinsics:` radar) and that the others are not used, and returns the summary's
/// record of it ({"radars_listed": N, "radars_used": [...]}); null for a one-radar dataset.
nlohmann::json ReportRadarsUsed(const io::DatasetConfig &dataset, const std::string &arg,
                                const std::string &command);
/// The description for `--radars CHOICE` on a dataset with a `radars:` list: "first" (or "") the
/// `folder:` + `extrinsics:` radar as described; a radar's name that radar alone (io::ForRadar).
/// Throws io::ConfigError naming the option, the radars' names and the closest choice (with "all"
/// among them when @p all_allowed: `dorado map`) for an unknown name.
[[nodiscard]] io::DatasetConfig SelectRadar(const io::DatasetConfig &dataset,
                                            const std::string &choice, bool all_allowed = false);
/// Writes out_dir/masks/NNNNNN.txt (NNNNNN = scan_index): a header naming the stamp and `legend`
/// (what each label means), then one label per point in input order.
void WriteMaskFile(const std::string &out_dir, std::size_t scan_index, int64_t stamp_ns,
                   const std::string &legend, const std::vector<int> &labels);
/// Adds the loop's skip and warning lists and counts to summary.json.
void AddStreamCounts(const ScanLoop &loop, nlohmann::json &summary);
/// Writes out_dir/summary.json atomically.
void WriteSummary(const std::string &out_dir, const nlohmann::json &summary);
/// Counts kept by cause as summary.json's {"key": count}, `key(cause)` giving the cause's stable
/// text.
template <typename Cause, typename Key>
[[nodiscard]] nlohmann::json CountsByKey(const std::map<Cause, int> &counts, Key key) {
    nlohmann::json json = nlohmann::json::object();
    for (const auto &[cause, count] : counts) json[std::string(key(cause))] = count;
    return json;
}
/// The same for an enum keyed by its own ToString (found in the enum's namespace).
template <typename Cause>
[[nodiscard]] nlohmann::json CountsByKey(const std::map<Cause, int> &counts) {
    return CountsByKey(counts, [](Cause cause) { return ToString(cause); });
}

}  // namespace dorado::apps
