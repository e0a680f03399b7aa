// rosbag2 recordings without their libraries (DORADO_WITH_ROSBAG2=OFF, or sqlite3, zstd, lz4,
// zlib or Fast-CDR absent at configure time): a .db3 / .mcap is refused with a message.
#include "dorado/io/recorded_messages.hpp"
#include "readers.hpp"

namespace dorado::io {
namespace {

[[noreturn]] void Refuse(const DatasetConfig &config) {
    throw DatasetError(config.rosbag.path +
                       ": a rosbag2 recording, but dorado was built without rosbag2 support "
                       "(libsqlite3-dev, libzstd-dev, liblz4-dev, zlib1g-dev, libfastcdr-dev)");
}

}  // namespace

std::unique_ptr<RecordedMessages> OpenRecordedMessages(const std::string &path,
                                                       const std::set<std::string> &) {
    throw DatasetError(path +
                       ": dorado was built without rosbag2 support (libsqlite3-dev, "
                       "libzstd-dev, liblz4-dev, zlib1g-dev, libfastcdr-dev)");
}

std::vector<TopicSummary> ListRosbag2Topics(const DatasetConfig &config) {
    Refuse(config);
}

std::unique_ptr<DatasetReader> OpenRosbag2Reader(const DatasetConfig &config) {
    Refuse(config);
}

}  // namespace dorado::io
