// ROS1 bags without rosbag_storage (DORADO_WITH_ROS1=OFF, or librosbag-storage-dev absent at
// configure time): a .bag is refused with a message.
#include "readers.hpp"

namespace dorado::io {
namespace {

[[noreturn]] void Refuse(const DatasetConfig &config) {
    throw DatasetError(config.rosbag.path +
                       ": a ROS1 bag, but dorado was built without ROS1 support (install "
                       "librosbag-storage-dev and configure with DORADO_WITH_ROS1=ON)");
}

}  // namespace

std::vector<TopicSummary> ListBagTopics(const DatasetConfig &config) {
    Refuse(config);
}

std::unique_ptr<DatasetReader> OpenBagReader(const DatasetConfig &config) {
    Refuse(config);
}

}  // namespace dorado::io
