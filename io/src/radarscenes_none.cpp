// RadarScenes without the HDF5 C library (DORADO_WITH_HDF5=OFF, or libhdf5-dev absent at configure
// time): a sequence is refused with a message, from its mount on (read when the description is).
#include <filesystem>

#include "readers.hpp"

namespace dorado::io {
namespace {

[[noreturn]] void Refuse(const DatasetConfig &config) {
    const std::string h5 =
        (std::filesystem::path(config.radarscenes.sequence_dir) / "radar_data.h5").string();
    throw DatasetError(h5 +
                       ": a RadarScenes sequence, but dorado was built without HDF5 support "
                       "(install libhdf5-dev and configure with DORADO_WITH_HDF5=ON)");
}

}  // namespace

std::unique_ptr<DatasetReader> OpenRadarScenesReader(const DatasetConfig &config,
                                                     const std::vector<int> &) {
    Refuse(config);
}

Trajectory LoadRadarScenesOdometry(const DatasetConfig &config) {
    Refuse(config);
}

Eigen::Isometry3d RadarScenesMount(const DatasetConfig &config) {
    Refuse(config);
}

std::vector<RadarStream> RadarScenesRadars(const DatasetConfig &config) {
    Refuse(config);
}

}  // namespace dorado::io
