#pragma once
/// @file dataset.hpp
/// A recorded dataset read as one stream of time-ordered events: radar scans, IMU samples and
/// ground-truth poses. Readers stream (they never load a whole bag) and report bad scans as
/// events instead of stopping.

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "dorado/core/imu.hpp"
#include "dorado/core/radar_scan.hpp"
#include "dorado/core/trajectory.hpp"
#include "dorado/io/dataset_config.hpp"

namespace dorado::io {

struct DatasetEvent {
    enum class Kind { kRadarScan, kImu, kGroundTruth, kBadScan };
    Kind kind = Kind::kRadarScan;
    int64_t stamp_ns = 0;
    std::size_t scan_index =
        0;           ///< index of the radar message in the dataset (for kRadarScan/kBadScan)
    RadarScan scan;  ///< kRadarScan: finite points only
    Eigen::Index removed_nonfinite_points = 0;  ///< kRadarScan: points dropped for NaN/Inf values
    ImuSample imu;                              ///< kImu
    StampedPose ground_truth;  ///< kGroundTruth: T_world_body of the ground-truth body
    std::string problem;       ///< kBadScan: why the scan could not be read
    /// kRadarScan/kBadScan from OpenRadars: the radar's index in the `radars:` list (0 otherwise);
    /// scan_index then counts that radar's messages.
    std::size_t radar = 0;
};

/// A fatal problem with the dataset (cannot open, unreadable index, missing topic): the message
/// names the file and what is wrong.
class DatasetError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

class DatasetReader {
  public:
    virtual ~DatasetReader() = default;
    /// Fills the next event; false at the end. Throws DatasetError on an unrecoverable problem.
    virtual bool Next(DatasetEvent &event) = 0;
    /// Human-readable name of the source (file or folder) for messages.
    [[nodiscard]] virtual std::string source() const = 0;
};

/// Opens the reader the config asks for. Throws DatasetError.
[[nodiscard]] std::unique_ptr<DatasetReader> OpenDataset(const DatasetConfig &config);

/// Every radar of the `radars:` list as one stream in time order: each radar's scans (event.radar
/// its index) merged by stamp, with the IMU file's samples once. A one-radar description is
/// OpenDataset. Throws DatasetError naming the radar whose first scan is more than
/// kMaxRadarClockOffsetS from the first radar's (another time base: a clock in seconds since boot
/// beside one in Unix time, microseconds read as nanoseconds).
[[nodiscard]] std::unique_ptr<DatasetReader> OpenRadars(const DatasetConfig &config);
inline constexpr double kMaxRadarClockOffsetS = 60.0;

}  // namespace dorado::io

namespace dorado::io {

/// What one topic (or, for a folder, the scan files) holds.
struct TopicSummary {
    std::string topic;
    std::string type;
    std::size_t messages = 0;
    int64_t first_ns = 0;  ///< record time of the first message
    int64_t last_ns = 0;
    std::string fields;  ///< point fields of the first message (point clouds only)
};

/// Every topic in the config's bag (or the scan folder as one topic), from the index only.
/// Throws DatasetError.
[[nodiscard]] std::vector<TopicSummary> ListTopics(const DatasetConfig &config);

/// The ground truth the config names: its trajectory file, else its ground-truth topic in the bag.
/// Empty when the dataset has none. Throws TrajectoryFileError / DatasetError naming the file.
[[nodiscard]] std::optional<Trajectory> LoadGroundTruth(const DatasetConfig &config);

}  // namespace dorado::io
