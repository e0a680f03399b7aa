#pragma once
/// @file recorded_messages.hpp
/// A rosbag2 recording (a folder with metadata.yaml, or one .db3 or .mcap) as one stream of its
/// serialized messages in log-time order, the storage files merged: what `dorado replay` publishes
/// and what the rosbag2 dataset reader decodes.

#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace dorado::io {

struct RecordedTopic {
    std::string name;
    std::string type;  ///< e.g. sensor_msgs/msg/PointCloud2
};

/// One serialized message (CDR, with its encapsulation header), or (problem non-empty, data
/// empty) a damaged part of a file that was skipped: the stream goes on after it.
struct RecordedMessage {
    std::string topic;
    int64_t log_time_ns = 0;  ///< the time the recorder received it
    std::vector<uint8_t> data;
    std::string problem;
};

class RecordedMessages {
  public:
    virtual ~RecordedMessages() = default;
    /// Every topic the files declare, with its type (each name once).
    [[nodiscard]] virtual const std::vector<RecordedTopic> &topics() const = 0;
    /// The next message on a selected topic (or a problem, first); false at the end.
    virtual bool Next(RecordedMessage &message) = 0;
};

/// Opens the recording at `path` on the `selected` topics (empty: all). Throws DatasetError naming
/// the path when it is not a rosbag2 recording or cannot be opened, or when dorado was built
/// without rosbag2 support.
[[nodiscard]] std::unique_ptr<RecordedMessages> OpenRecordedMessages(
    const std::string &path, const std::set<std::string> &selected);

}  // namespace dorado::io
