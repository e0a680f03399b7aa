// An IMU file beside the scans (the `imu:` section): the nuScenes CAN bus expansion's
// SCENE_ms_imu.json, read and merged into a scan folder's stream in time order. Truths: the values
// written by hand below, and, when ../shared/data/real is present, the nuScenes reference poses
// (the gyro's integrated yaw against the ego poses' heading change).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "dorado/core/lie.hpp"
#include "dorado/io/dataset.hpp"
#include "dorado/io/trajectory_io.hpp"
#include "dorado/testing/dataset_events.hpp"

namespace dorado::io {
namespace {

namespace fs = std::filesystem;

class ImuFileTest : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = fs::path(::testing::TempDir()) / ("dorado_imu_file_" + std::to_string(::getpid()));
        fs::create_directories(dir_ / "scans");
        // Three scans of one point (x y z v) at 0.10, 0.20 and 0.30 s.
        for (int k = 0; k < 3; ++k) {
            char name[16];
            std::snprintf(name, sizeof(name), "%05d.bin", k);
            const float row[4] = {10.0F, 1.0F, 0.0F, -2.0F};
            std::ofstream(dir_ / "scans" / name, std::ios::binary)
                .write(reinterpret_cast<const char *>(row), sizeof(row));
        }
        std::ofstream(dir_ / "times.txt") << "0.10\n0.20\n0.30\n";
    }
    void TearDown() override { fs::remove_all(dir_); }

    // Records at `utimes_us`, sample k with gyro (0.01 k, -0.02, 0.1 + k) and accel (k, 0, 9.8).
    std::string WriteImu(const std::vector<int64_t> &utimes_us) {
        std::ostringstream json;
        json << "[";
        for (std::size_t k = 0; k < utimes_us.size(); ++k) {
            json << (k ? "," : "") << "{\"utime\":" << utimes_us[k] << ",\"linear_accel\":[" << k
                 << ",0,9.8],\"q\":[1,0,0,0],"
                 << "\"rotation_rate\":[" << 0.01 * static_cast<double>(k) << ",-0.02,"
                 << 0.1 + static_cast<double>(k) << "]}";
        }
        json << "]";
        return WriteText(json.str());
    }
    std::string WriteText(const std::string &text) {
        const fs::path path = dir_ / "scene-0001_ms_imu.json";
        std::ofstream(path) << text;
        return path.string();
    }

    DatasetConfig Config(const std::string &imu_path) const {
        DatasetConfig config;
        config.reader = ReaderKind::kFolder;
        config.folder.scans_dir = (dir_ / "scans").string();
        config.folder.timestamps_file = (dir_ / "times.txt").string();
        config.folder.columns = {"x", "y", "z", "v"};
        config.fields.range = config.fields.azimuth = config.fields.elevation = "";
        config.fields.power = "";
        config.fields.doppler = "v";
        config.imu.path = imu_path;
        return config;
    }

    fs::path dir_;
};

TEST_F(ImuFileTest, SamplesGoOutBeforeTheFirstScanAfterThemWithTheirValues) {
    // 0.05, 0.10 (the first scan's stamp: in its interval), 0.15, 0.25 and 0.35 s (after the last).
    const auto events =
        testing::ReadAllEvents(Config(WriteImu({50000, 100000, 150000, 250000, 350000})));
    std::string order;
    for (const auto &e : events) order += e.kind == DatasetEvent::Kind::kImu ? 'i' : 's';
    EXPECT_EQ(order, "iisisisi");
    std::vector<ImuSample> imu;
    for (const auto &e : events) {
        if (e.kind != DatasetEvent::Kind::kImu) continue;
        EXPECT_EQ(e.stamp_ns, e.imu.stamp_ns);
        imu.push_back(e.imu);
    }
    ASSERT_EQ(imu.size(), 5U);
    EXPECT_EQ(imu[1].stamp_ns, 100'000'000);
    EXPECT_EQ(imu[3].stamp_ns, 250'000'000);
    EXPECT_DOUBLE_EQ(imu[3].omega_imu_radps.x(), 0.03);
    EXPECT_DOUBLE_EQ(imu[3].omega_imu_radps.y(), -0.02);
    EXPECT_DOUBLE_EQ(imu[3].omega_imu_radps.z(), 3.1);
    EXPECT_DOUBLE_EQ(imu[3].accel_imu_mps2.x(), 3.0);
    EXPECT_DOUBLE_EQ(imu[3].accel_imu_mps2.z(), 9.8);
}

TEST_F(ImuFileTest, ListTopicsShowsTheFileBesideTheScans) {
    const std::string path = WriteImu({50000, 150000, 250000});
    const auto topics = ListTopics(Config(path));
    ASSERT_EQ(topics.size(), 2U);
    EXPECT_EQ(topics[0].messages, 3U);
    EXPECT_EQ(topics[1].topic, path);
    EXPECT_EQ(topics[1].messages, 3U);
    EXPECT_EQ(topics[1].first_ns, 50'000'000);
    EXPECT_EQ(topics[1].last_ns, 250'000'000);
}

TEST_F(ImuFileTest, BadFilesAreRefusedNamingTheFileAndTheRecord) {
    const std::string good =
        R"({"utime":1,"linear_accel":[0,0,9.8],"q":[1,0,0,0],"rotation_rate":[0,0,0]})";
    const struct {
        std::string text, expected;
    } cases[] = {
        {"[" + good + R"(,{"utime":2,"linear_accel":[0,0,9.8]}])", "record 1"},
        {"[" + good + R"(,{"utime":2,"linear_accel":[0,9.8],"rotation_rate":[0,0,0]}])",
         "record 1: linear_accel needs 3 values"},
        {"[" + good + "," + good + "]", "record 1: utime 1 us is not after"},
        {"[" + good + R"(,{"utime":2,"linear_ac)", "not valid JSON"},
        {"[]", "no IMU record"},
        {R"({"utime":1})", "not a list"},
    };
    for (const auto &c : cases) {
        const std::string path = WriteText(c.text);
        const std::string message = testing::ReadAllEventsError(Config(path));
        EXPECT_NE(message.find(path), std::string::npos) << c.text << " -> " << message;
        EXPECT_NE(message.find(c.expected), std::string::npos) << c.text << " -> " << message;
    }
    EXPECT_NE(
        testing::ReadAllEventsError(Config((dir_ / "missing.json").string())).find("cannot open"),
        std::string::npos);
}

TEST_F(ImuFileTest, TheDescriptionReadsAndWritesTheSection) {
    const std::string imu_path = WriteImu({50000});
    const fs::path yaml = dir_ / "dataset.yaml";
    std::ofstream(yaml) << "reader: folder\nfolder: {scans_dir: scans, timestamps_file: times.txt, "
                           "columns: [x, y, z, v]}\nfields: {range: '', azimuth: '', elevation: "
                           "'', power: '', doppler: v}\nimu: {path: scene-0001_ms_imu.json, "
                           "format: nuscenes_can_bus}\n";
    const DatasetConfig config = LoadDatasetConfig(yaml.string());
    EXPECT_EQ(fs::path(config.imu.path), fs::path(imu_path));
    EXPECT_EQ(config.imu.format, ImuFileFormat::kNuScenesCanBus);
    std::ofstream(dir_ / "copy.yaml") << DatasetConfigToYaml(config);
    EXPECT_EQ(LoadDatasetConfig((dir_ / "copy.yaml").string()).imu.path, config.imu.path);

    const auto refused = [&](const std::string &text) {
        std::ofstream(yaml) << text;
        try {
            (void)LoadDatasetConfig(yaml.string());
        } catch (const ConfigError &e) {
            return std::string(e.what());
        }
        return std::string();
    };
    const std::string bag = refused("reader: rosbag\nrosbag: {path: x.bag}\nimu: {path: a.json}\n");
    EXPECT_NE(bag.find("imu.path"), std::string::npos) << bag;
    EXPECT_NE(bag.find("rosbag.imu_topic"), std::string::npos) << bag;
    const std::string format = refused(
        "reader: folder\nfolder: {scans_dir: scans, timestamps_file: times.txt, columns: [x, y, "
        "z, v]}\nimu: {path: a.json, format: csv}\n");
    EXPECT_NE(format.find("nuscenes_can_bus"), std::string::npos) << format;
}

TEST(ImuFileShared, TheNuScenesGyroIntegratesToTheReferenceHeadingChange) {
    const fs::path scene =
        fs::path(DORADO_SOURCE_DIR) / ".." / "shared" / "data" / "real" / "nuscenes_scene-0061";
    if (!fs::exists(scene / "can_bus" / "scene-0061_ms_imu.json"))
        GTEST_SKIP() << "no " << scene << " (../shared/data/real)";
    DatasetConfig config;
    config.reader = ReaderKind::kFolder;
    config.folder.scans_dir = (scene / "radar_front" / "scans").string();
    config.folder.timestamps_file = (scene / "radar_front" / "times.txt").string();
    config.folder.columns = {"x", "y", "z", "rcs", "v_r", "_"};
    config.fields.range = config.fields.azimuth = config.fields.elevation = "";
    config.fields.power = "rcs";
    config.fields.doppler = "v_r";
    config.imu.path = (scene / "can_bus" / "scene-0061_ms_imu.json").string();
    const Trajectory reference = ReadTum((scene / "ground_truth.tum").string());
    const int64_t t0_ns = reference.poses().front().stamp_ns;
    const int64_t t1_ns = reference.poses().back().stamp_ns;
    auto reader = OpenDataset(config);
    DatasetEvent e;
    double yaw = 0.0;
    int64_t last_ns = -1, first_ns = 0, end_ns = 0;
    std::size_t samples = 0, scans = 0;
    while (reader->Next(e)) {
        if (e.kind == DatasetEvent::Kind::kRadarScan) ++scans;
        if (e.kind != DatasetEvent::Kind::kImu) continue;
        ++samples;
        if (e.stamp_ns < t0_ns || e.stamp_ns > t1_ns) continue;  // outside the reference
        ASSERT_GT(e.stamp_ns, last_ns);
        if (last_ns >= 0) yaw += e.imu.omega_imu_radps.z() * 1e-9 * double(e.stamp_ns - last_ns);
        if (last_ns < 0) first_ns = e.stamp_ns;
        last_ns = end_ns = e.stamp_ns;
    }
    EXPECT_EQ(scans, 247U);
    EXPECT_GT(samples, 1800U);  // 100 Hz over 19 s
    const auto heading = [&](int64_t t_ns) {
        const Eigen::Matrix3d R = reference.Interpolate(t_ns).value().linear();
        return std::atan2(R(1, 0), R(0, 0));
    };
    double turned = heading(end_ns) - heading(first_ns);
    turned = std::remainder(turned, 2.0 * M_PI);
    EXPECT_NEAR(yaw, turned, 0.03 * std::abs(turned)) << "integrated gyro " << yaw;
}

}  // namespace
}  // namespace dorado::io
