#pragma once
// Private to dorado_io: the concrete readers behind OpenDataset.

#include <filesystem>
#include <memory>

#include "dorado/io/dataset.hpp"
#include "dorado/io/folder_layout.hpp"

namespace dorado::io {

[[nodiscard]] std::unique_ptr<DatasetReader> OpenBagReader(const DatasetConfig &config);
[[nodiscard]] std::unique_ptr<DatasetReader> OpenFolderReader(const DatasetConfig &config);

/// The data sets' own formats (dataset_config.hpp: RadarScenesSource, NuScenesSource): the scans of
/// the radars given, merged in time order, event.radar the radar's index in the list and
/// event.scan_index counting that radar's scans. Throws DatasetError.
[[nodiscard]] std::unique_ptr<DatasetReader> OpenRadarScenesReader(
    const DatasetConfig &config, const std::vector<int> &sensor_ids);
[[nodiscard]] std::unique_ptr<DatasetReader> OpenNuScenesReader(
    const DatasetConfig &config, const std::vector<std::string> &channels);
/// The one radar a description reads when a command reads one: radarscenes.sensor_id /
/// nuscenes.channel, or with every radar the first of `radars:`.
[[nodiscard]] int OneRadarScenesSensor(const DatasetConfig &config);
[[nodiscard]] std::string OneNuScenesChannel(const DatasetConfig &config);
/// radarscenes.sequence_dir without "." / ".." parts and without a trailing separator, so that its
/// parent_path() is the folder above it (a DatasetConfig built in code is not normalised).
[[nodiscard]] std::filesystem::path RadarScenesSequenceDir(const DatasetConfig &config);
/// T_base_radar of the one radar as the data set publishes it (sensors.json; calibrated_sensor).
/// Throws DatasetError.
[[nodiscard]] Eigen::Isometry3d RadarScenesMount(const DatasetConfig &config);
[[nodiscard]] Eigen::Isometry3d NuScenesMount(const DatasetConfig &config);
/// Every radar of the sequence (sensors.json's radar_<id> with scans in scenes.json, by id) or of
/// the scene (its RADAR_* channels with sweeps, front first), each with its published mount.
/// Throws DatasetError.
[[nodiscard]] std::vector<RadarStream> RadarScenesRadars(const DatasetConfig &config);
[[nodiscard]] std::vector<RadarStream> NuScenesRadars(const DatasetConfig &config);
/// The data set's reference trajectory of the base (RadarScenes' odometry table; nuScenes' ego
/// poses of the scene). Throws DatasetError.
[[nodiscard]] Trajectory LoadRadarScenesOdometry(const DatasetConfig &config);
[[nodiscard]] Trajectory LoadNuScenesEgoPoses(const DatasetConfig &config);

/// The samples of an IMU file (ImuFile), in time order. Throws DatasetError naming the file and
/// the record (unreadable, a missing or malformed field, stamps not increasing, no record).
[[nodiscard]] std::vector<ImuSample> ReadImuFile(const ImuFile &file);
/// @p scans' events with the file's IMU samples merged in time order (each sample before the
/// first scan stamped after it). Throws DatasetError as ReadImuFile.
[[nodiscard]] std::unique_ptr<DatasetReader> WithImuFile(std::unique_ptr<DatasetReader> scans,
                                                         const ImuFile &file);

[[nodiscard]] std::unique_ptr<DatasetReader> OpenRosbag2Reader(const DatasetConfig &config);
/// rosbag.path's recording, ROS1 or rosbag2, whichever its bytes say it is.
[[nodiscard]] std::unique_ptr<DatasetReader> OpenRecordingReader(const DatasetConfig &config);

[[nodiscard]] std::vector<TopicSummary> ListBagTopics(const DatasetConfig &config);
[[nodiscard]] std::vector<TopicSummary> ListRosbag2Topics(const DatasetConfig &config);

/// The folder's scan files with its extension, sorted. Throws DatasetError (no folder, no files).
[[nodiscard]] std::vector<std::string> ListScanFiles(const FolderSource &folder);
/// CheckFolderLayout on an already listed folder.
[[nodiscard]] std::optional<FolderLayoutProblem> CheckFolderFiles(
    const DatasetConfig &config, const std::vector<std::string> &files);

/// Decimal seconds to integer nanoseconds without rounding through a double; false if malformed.
bool ParseSecondsToNanos(const std::string &token, int64_t &ns);

}  // namespace dorado::io
