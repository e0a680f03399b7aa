#pragma once
// Private to dorado_io: the two rosbag2 storage formats (sqlite3 .db3 and MCAP) as one kind of
// message stream, and the detection of a recording's format from its bytes.

#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "dorado/io/recorded_messages.hpp"

namespace dorado::io {

/// How a recording is stored, found from the file's first bytes (not its name).
enum class BagFormat { kRos1, kRosbag2Folder, kSqlite3, kMcap };

/// The format of a ROS1 .bag, a rosbag2 folder (with metadata.yaml), a .db3 or an .mcap.
/// Throws DatasetError naming the path when it is none of these.
[[nodiscard]] BagFormat DetectBagFormat(const std::string &path);

using Rosbag2Topic = RecordedTopic;
/// One serialized message, or (problem non-empty, data empty) a damaged part of the file that was
/// skipped: the stream goes on after it unless the storage says it ended.
using Rosbag2Message = RecordedMessage;

/// One storage file, streamed in log-time order: a recording of one file.
using Rosbag2Storage = RecordedMessages;

/// Opens a file; `selected` names the topics to stream (empty = all). Throws DatasetError when the
/// file cannot be opened at all.
[[nodiscard]] std::unique_ptr<Rosbag2Storage> OpenSqliteStorage(
    const std::string &path, const std::set<std::string> &selected);
[[nodiscard]] std::unique_ptr<Rosbag2Storage> OpenMcapStorage(
    const std::string &path, const std::set<std::string> &selected);

/// Every storage file of a recording, each open on the selected topics (empty: all).
[[nodiscard]] std::vector<std::unique_ptr<Rosbag2Storage>> OpenRosbag2Storages(
    const std::string &path, const std::set<std::string> &selected);

/// The storage files of a recording: the folder's metadata.yaml list, or the one file.
[[nodiscard]] std::vector<std::string> Rosbag2Files(const std::string &path, BagFormat format);

}  // namespace dorado::io
