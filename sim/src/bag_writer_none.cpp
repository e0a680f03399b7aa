// The bag writer without rosbag_storage (DORADO_WITH_ROS1=OFF, or librosbag-storage-dev absent at
// configure time): creating a bag throws, so `dorado simulate` stops with a message before writing.
#include <stdexcept>

#include "dorado/sim/bag_writer.hpp"

namespace dorado::sim {

struct BagWriter::Impl {};

BagWriter::BagWriter(const std::string &path) : path_(path) {
    throw std::runtime_error(path +
                             ": cannot create the bag: dorado was built without ROS1 support "
                             "(install librosbag-storage-dev and configure with "
                             "DORADO_WITH_ROS1=ON)");
}

BagWriter::~BagWriter() = default;

void BagWriter::WriteRadar(const std::string &, const RadarScan &) {}
void BagWriter::WriteImu(const std::string &, const std::string &, const ImuSample &) {}
void BagWriter::WriteOdometry(const std::string &, const std::string &, const std::string &,
                              int64_t, const Eigen::Isometry3d &) {}
void BagWriter::Close() {}

}  // namespace dorado::sim
