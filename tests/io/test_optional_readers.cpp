// The optional readers (io/CMakeLists.txt: DORADO_WITH_ROS1, DORADO_WITH_ROSBAG2,
// DORADO_WITH_HDF5): a build without one refuses its recordings with a message naming the file and
// what to install; a build with it reads them (these files are not valid recordings: some other
// error, never the refusal).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "dorado/io/dataset.hpp"

namespace dorado::io {
namespace {

namespace fs = std::filesystem;

class OptionalReaders : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = fs::path(::testing::TempDir()) / ("dorado_optional_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    // A recording that starts with `magic` (what DetectBagFormat looks at) and holds nothing else.
    DatasetConfig Recording(const std::string &name, const std::string &magic) {
        std::ofstream(dir_ / name, std::ios::binary).write(magic.data(), magic.size());
        DatasetConfig config;
        config.reader = ReaderKind::kRosbag;
        config.rosbag.path = (dir_ / name).string();
        return config;
    }

    // The message OpenDataset throws (every reader throws on these files).
    static std::string ErrorOf(const DatasetConfig &config) {
        try {
            (void)OpenDataset(config);
        } catch (const std::exception &e) {
            return e.what();
        }
        ADD_FAILURE() << "OpenDataset did not throw";
        return "";
    }

    // Built: any error but the refusal. Left out: the refusal, naming `file` and `install`.
    static void ExpectRefusedUnlessBuilt(bool built, const std::string &message,
                                         const std::string &file, const std::string &install) {
        if (built) {
            EXPECT_EQ(message.find("dorado was built without"), std::string::npos) << message;
            return;
        }
        EXPECT_EQ(message.rfind(file + ": ", 0), 0U) << message;
        EXPECT_NE(message.find("dorado was built without"), std::string::npos) << message;
        EXPECT_NE(message.find(install), std::string::npos) << message;
    }

    fs::path dir_;
};

TEST_F(OptionalReaders, Ros1Bag) {
    const DatasetConfig config = Recording("x.bag", "#ROSBAG V2.0\n");
    ExpectRefusedUnlessBuilt(DORADO_HAVE_ROS1, ErrorOf(config), config.rosbag.path,
                             "librosbag-storage-dev");
}

TEST_F(OptionalReaders, Rosbag2Sqlite) {
    const DatasetConfig config = Recording("x.db3", std::string("SQLite format 3\0", 16));
    ExpectRefusedUnlessBuilt(DORADO_HAVE_ROSBAG2, ErrorOf(config), config.rosbag.path,
                             "libsqlite3-dev");
}

TEST_F(OptionalReaders, RadarScenesHdf5) {
    DatasetConfig config;
    config.reader = ReaderKind::kRadarScenes;
    config.radarscenes.sequence_dir = dir_.string();
    config.radarscenes.sensor_id = 1;
    ExpectRefusedUnlessBuilt(DORADO_HAVE_HDF5, ErrorOf(config), (dir_ / "radar_data.h5").string(),
                             "libhdf5-dev");
}

}  // namespace
}  // namespace dorado::io
