// Bags written at test time by the real ROS tool (Debian's python3-rosbag), read back exactly.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "dorado/io/dataset.hpp"
#include "dorado/testing/dataset_events.hpp"

namespace dorado::io {
namespace {

constexpr int kPoints = 12;
constexpr int kScans = 5;

/// The formula of make_test_bags.py: x, y, z, range, elevation, azimuth, power, doppler.
std::array<float, 8> ExpectedPoint(int k, int i) {
    return {0.5f * i + k,
            -0.25f * i,
            0.125f * i - 1.0f,
            2.0f + i,
            static_cast<float>(0.01 * i),
            static_cast<float>(-0.02 * i),
            10.0f + i,
            static_cast<float>(0.1 * i - 0.5)};
}

int64_t ExpectedStamp(int k) {
    return (1690000000LL + k / 10) * 1000000000LL + (k % 10) * 100000000LL + 123;
}

class BagReaderTest : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        dir_ = std::filesystem::path(::testing::TempDir()) /
               ("dorado_bags_" + std::to_string(::getpid()));
        const std::string cmd = std::string(DORADO_SYSTEM_PYTHON) + " " + DORADO_SOURCE_DIR +
                                "/tests/io/make_test_bags.py " + dir_.string();
        ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    }
    static void TearDownTestSuite() { std::filesystem::remove_all(dir_); }

    static DatasetConfig Config(const std::string &bag) {
        DatasetConfig config;
        config.rosbag.path = (dir_ / bag).string();
        return config;
    }

    static void ExpectExactScan(const DatasetEvent &e, int k, bool spherical = true,
                                bool power = true) {
        ASSERT_EQ(e.kind, DatasetEvent::Kind::kRadarScan) << e.problem;
        ASSERT_EQ(e.scan.size(), kPoints);
        EXPECT_EQ(e.stamp_ns, ExpectedStamp(k));
        EXPECT_EQ(e.scan.stamp_ns, ExpectedStamp(k));
        for (int i = 0; i < kPoints; ++i) {
            const auto p = ExpectedPoint(k, i);
            EXPECT_EQ(e.scan.xyz_radar(0, i), p[0]);
            EXPECT_EQ(e.scan.xyz_radar(1, i), p[1]);
            EXPECT_EQ(e.scan.xyz_radar(2, i), p[2]);
            EXPECT_EQ(e.scan.doppler_mps[i], p[7]);
            if (power) {
                EXPECT_EQ(e.scan.power_db[i], p[6]);
            }
            if (spherical) {
                EXPECT_EQ(e.scan.range_m[i], p[3]);
                EXPECT_EQ(e.scan.elevation_rad[i], p[4]);
                EXPECT_EQ(e.scan.azimuth_rad[i], p[5]);
            }
        }
    }

    static std::filesystem::path dir_;
};
std::filesystem::path BagReaderTest::dir_;

TEST_F(BagReaderTest, HuginLayoutWithImuAndGroundTruthReadsBackExactly) {
    DatasetConfig config = Config("hugin.bag");
    config.rosbag.imu_topic = "/imu/data";
    config.rosbag.ground_truth_topic = "/ground_truth/odom";
    const auto events = testing::ReadAllEvents(config);
    ASSERT_EQ(events.size(), 3u * kScans);
    int scans = 0, imu = 0, gt = 0;
    int64_t last = 0;
    for (const auto &e : events) {
        EXPECT_GE(e.stamp_ns, last) << "events must come in time order";
        last = e.stamp_ns;
        switch (e.kind) {
            case DatasetEvent::Kind::kRadarScan:
                ExpectExactScan(e, scans);
                EXPECT_EQ(e.scan.frame_id, "radar");
                EXPECT_EQ(e.scan_index, static_cast<std::size_t>(scans));
                EXPECT_TRUE(e.scan.has_power);
                ++scans;
                break;
            case DatasetEvent::Kind::kImu:
                EXPECT_DOUBLE_EQ(e.imu.omega_imu_radps.x(), 0.01 * imu);
                EXPECT_DOUBLE_EQ(e.imu.omega_imu_radps.z(), -0.03);
                EXPECT_DOUBLE_EQ(e.imu.accel_imu_mps2.z(), 9.81);
                ++imu;
                break;
            case DatasetEvent::Kind::kGroundTruth:
                EXPECT_DOUBLE_EQ(e.ground_truth.T_world_body.translation().x(), 1.5 * gt);
                EXPECT_EQ(e.ground_truth.stamp_ns, ExpectedStamp(gt));
                ++gt;
                break;
            case DatasetEvent::Kind::kBadScan:
                ADD_FAILURE() << e.problem;
        }
    }
    EXPECT_EQ(scans, kScans);
    EXPECT_EQ(imu, kScans);
    EXPECT_EQ(gt, kScans);
}

TEST_F(BagReaderTest, PoseStampedGroundTruthThroughLoadGroundTruth) {
    DatasetConfig config = Config("hugin.bag");
    config.rosbag.ground_truth_topic = "/ground_truth/pose";
    const auto gt = LoadGroundTruth(config);
    ASSERT_TRUE(gt.has_value());
    ASSERT_EQ(gt->size(), static_cast<std::size_t>(kScans));
    EXPECT_DOUBLE_EQ((*gt)[3].T_world_body.translation().y(), -6.0);
    // Orientation (qz, qw) = (0.6, 0.8): a yaw of 2 atan2(0.6, 0.8).
    const Eigen::AngleAxisd aa((*gt)[0].T_world_body.linear());
    EXPECT_NEAR(aa.angle(), 2 * std::atan2(0.6, 0.8), 1e-12);
}

TEST_F(BagReaderTest, BigEndianLayoutReadsBackExactly) {
    const auto events = testing::ReadAllEvents(Config("bigendian.bag"));
    ASSERT_EQ(events.size(), static_cast<std::size_t>(kScans));
    for (int k = 0; k < kScans; ++k) ExpectExactScan(events[k], k);
}

TEST_F(BagReaderTest, Float64AndInt16FieldsWithPaddedRowsReadBackExactly) {
    DatasetConfig config = Config("float64.bag");
    config.rosbag.radar_topic = "/radar/points";
    config.fields.x = "px";
    config.fields.y = "py";
    config.fields.z = "pz";
    config.fields.doppler = "vr";
    config.fields.power = "rcs";
    config.fields.range = config.fields.azimuth = config.fields.elevation = "";
    const auto events = testing::ReadAllEvents(config);
    ASSERT_EQ(events.size(), static_cast<std::size_t>(kScans));
    for (int k = 0; k < kScans; ++k) {
        // float64 fields carry the double formula; compare with the float32 values widened, which
        // the python formula matches except where float32 rounds: use the double formula directly.
        const auto &scan = events[k].scan;
        ASSERT_EQ(events[k].kind, DatasetEvent::Kind::kRadarScan) << events[k].problem;
        ASSERT_EQ(scan.size(), kPoints);
        for (int i = 0; i < kPoints; ++i) {
            EXPECT_EQ(scan.xyz_radar(0, i), 0.5 * i + k);
            EXPECT_EQ(scan.xyz_radar(2, i), 0.125 * i - 1.0);
            EXPECT_EQ(scan.doppler_mps[i], 0.1 * i - 0.5);
            EXPECT_EQ(scan.power_db[i], 10.0 + i);
            EXPECT_DOUBLE_EQ(scan.range_m[i], scan.xyz_radar.col(i).norm()) << "derived from xyz";
        }
    }
}

TEST_F(BagReaderTest, PointCloudWithChannels) {
    DatasetConfig config = Config("channels.bag");
    config.rosbag.radar_topic = "/radar/cloud";
    config.fields.doppler = "Doppler";
    config.fields.power = "Power";
    const auto events = testing::ReadAllEvents(config);
    ASSERT_EQ(events.size(), static_cast<std::size_t>(kScans));
    for (int k = 0; k < kScans; ++k) ExpectExactScan(events[k], k, /*spherical=*/false);
}

TEST_F(BagReaderTest, MissingFieldIsACountedBadScanNamingTheField) {
    DatasetConfig config = Config("bigendian.bag");
    config.fields.doppler = "velocity";
    const auto events = testing::ReadAllEvents(config);
    ASSERT_EQ(events.size(), static_cast<std::size_t>(kScans));
    for (const auto &e : events) {
        EXPECT_EQ(e.kind, DatasetEvent::Kind::kBadScan);
        EXPECT_NE(e.problem.find("bigendian.bag"), std::string::npos) << e.problem;
        EXPECT_NE(e.problem.find("missing field 'velocity'"), std::string::npos) << e.problem;
        EXPECT_NE(e.problem.find("doppler:FLOAT32"), std::string::npos)
            << "lists the fields present";
    }
}

TEST_F(BagReaderTest, NanPointsAreRemovedAndCountedAndBackwardStampsDelivered) {
    const auto events = testing::ReadAllEvents(Config("faults.bag"));
    ASSERT_EQ(events.size(), static_cast<std::size_t>(kScans));
    EXPECT_EQ(events[2].removed_nonfinite_points, 1);
    EXPECT_EQ(events[2].scan.size(), kPoints - 1);
    EXPECT_EQ(events[3].stamp_ns, ExpectedStamp(1)) << "header stamp kept, the consumer decides";
}

TEST_F(BagReaderTest, MissingTopicListsWhatIsThere) {
    DatasetConfig config = Config("hugin.bag");
    config.rosbag.imu_topic = "/imu/raw";
    try {
        (void)OpenDataset(config);
        FAIL() << "expected DatasetError";
    } catch (const DatasetError &e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("'/imu/raw' is not in the bag"), std::string::npos) << what;
        EXPECT_NE(what.find("/imu/data [sensor_msgs/Imu]"), std::string::npos) << what;
    }
}

TEST_F(BagReaderTest, WrongTopicTypeIsRejectedAtOpen) {
    DatasetConfig config = Config("hugin.bag");
    config.rosbag.imu_topic = "/ground_truth/odom";
    EXPECT_THROW((void)OpenDataset(config), DatasetError);
}

TEST_F(BagReaderTest, TruncatedBagGivesAClearErrorNamingTheFile) {
    try {
        (void)OpenDataset(Config("truncated.bag"));
        FAIL() << "expected DatasetError";
    } catch (const DatasetError &e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("truncated.bag"), std::string::npos) << what;
        EXPECT_NE(what.find("rosbag reindex"), std::string::npos) << what;
    }
}

TEST_F(BagReaderTest, ListTopicsFromTheIndex) {
    const auto topics = ListTopics(Config("hugin.bag"));
    ASSERT_EQ(topics.size(), 4u);
    const auto radar = std::find_if(topics.begin(), topics.end(),
                                    [](auto &t) { return t.topic == "/hugin_raf_1/radar_data"; });
    ASSERT_NE(radar, topics.end());
    EXPECT_EQ(radar->messages, static_cast<std::size_t>(kScans));
    EXPECT_EQ(radar->type, "sensor_msgs/PointCloud2");
    EXPECT_NE(radar->fields.find("doppler:FLOAT32"), std::string::npos);
}

}  // namespace
}  // namespace dorado::io
