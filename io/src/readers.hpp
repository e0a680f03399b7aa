#pragma once
// Private to dorado_io: the concrete readers behind OpenDataset.

#include <memory>

#include "dorado/io/dataset.hpp"

namespace dorado::io {

[[nodiscard]] std::unique_ptr<DatasetReader> OpenBagReader(const DatasetConfig &config);
[[nodiscard]] std::unique_ptr<DatasetReader> OpenFolderReader(const DatasetConfig &config);

[[nodiscard]] std::unique_ptr<DatasetReader> OpenRosbag2Reader(const DatasetConfig &config);
/// rosbag.path's recording, ROS1 or rosbag2, whichever its bytes say it is.
[[nodiscard]] std::unique_ptr<DatasetReader> OpenRecordingReader(const DatasetConfig &config);

[[nodiscard]] std::vector<TopicSummary> ListBagTopics(const DatasetConfig &config);
[[nodiscard]] std::vector<TopicSummary> ListRosbag2Topics(const DatasetConfig &config);

/// Decimal seconds to integer nanoseconds without rounding through a double; false if malformed.
bool ParseSecondsToNanos(const std::string &token, int64_t &ns);

}  // namespace dorado::io
