// rosbag2 recordings (.db3, .mcap with zstd/lz4/no compression, a split folder) written at test
// time by tests/io/rosbag2_writer.py, which encodes CDR, sqlite3 and MCAP itself from the
// specifications, read back exactly; and the damaged ones, whose good scans must survive.
#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "dorado/io/dataset.hpp"
#include "dorado/testing/dataset_events.hpp"

namespace dorado::io {
namespace {

constexpr int kPoints = 12;
constexpr int kScans = 5;
constexpr const char *kRadar = "/hugin_raf_1/radar_data";

/// The formula of make_ros2_bags.py: x, y, z, range, elevation, azimuth, power, doppler.
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

class Rosbag2ReaderTest : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        dir_ = std::filesystem::path(::testing::TempDir()) /
               ("dorado_ros2_" + std::to_string(::getpid()));
        const std::string cmd = std::string(DORADO_SYSTEM_PYTHON) + " " + DORADO_SOURCE_DIR +
                                "/tests/io/make_ros2_bags.py fixtures " + dir_.string();
        ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    }
    static void TearDownTestSuite() { std::filesystem::remove_all(dir_); }

    static DatasetConfig Config(const std::string &bag, const std::string &gt = "") {
        DatasetConfig config;
        config.rosbag.path = (dir_ / bag).string();
        config.rosbag.ground_truth_topic = gt;
        return config;
    }

    static std::vector<DatasetEvent> OfKind(const std::vector<DatasetEvent> &events,
                                            DatasetEvent::Kind kind) {
        std::vector<DatasetEvent> out;
        for (const auto &e : events)
            if (e.kind == kind) out.push_back(e);
        return out;
    }

    static void ExpectExactScan(const DatasetEvent &e, int k) {
        ASSERT_EQ(e.kind, DatasetEvent::Kind::kRadarScan) << e.problem;
        ASSERT_EQ(e.scan.size(), kPoints);
        EXPECT_EQ(e.stamp_ns, ExpectedStamp(k));
        EXPECT_EQ(e.scan.frame_id, "radar");
        for (int i = 0; i < kPoints; ++i) {
            const auto p = ExpectedPoint(k, i);
            EXPECT_EQ(e.scan.xyz_radar(0, i), p[0]);
            EXPECT_EQ(e.scan.xyz_radar(1, i), p[1]);
            EXPECT_EQ(e.scan.xyz_radar(2, i), p[2]);
            EXPECT_EQ(e.scan.range_m[i], p[3]);
            EXPECT_EQ(e.scan.elevation_rad[i], p[4]);
            EXPECT_EQ(e.scan.azimuth_rad[i], p[5]);
            EXPECT_EQ(e.scan.power_db[i], p[6]);
            EXPECT_EQ(e.scan.doppler_mps[i], p[7]);
        }
    }

    /// The problems, one string each, after checking that the readable scans are exact.
    static std::vector<std::string> ScansAndProblems(const std::string &bag,
                                                     const std::vector<int> &good_scans) {
        const auto events = testing::ReadAllEvents(Config(bag));
        const auto scans = OfKind(events, DatasetEvent::Kind::kRadarScan);
        EXPECT_EQ(scans.size(), good_scans.size()) << bag;
        for (std::size_t j = 0; j < std::min(scans.size(), good_scans.size()); ++j)
            ExpectExactScan(scans[j], good_scans[j]);
        std::vector<std::string> problems;
        for (const auto &e : OfKind(events, DatasetEvent::Kind::kBadScan))
            problems.push_back(e.problem);
        return problems;
    }

    static std::filesystem::path dir_;
};

std::filesystem::path Rosbag2ReaderTest::dir_;

TEST_F(Rosbag2ReaderTest, EveryStorageGivesTheWrittenMessagesInTimeOrder) {
    for (const char *bag : {"known.db3", "known.mcap", "known_lz4.mcap", "known_raw.mcap",
                            "nosummary.mcap", "unchunked.mcap", "split"}) {
        SCOPED_TRACE(bag);
        DatasetConfig config = Config(bag, "/odom");
        config.rosbag.imu_topic = "/imu";
        const auto events = testing::ReadAllEvents(config);
        ASSERT_EQ(events.size(), 5u + 20u + 5u);
        const auto scans = OfKind(events, DatasetEvent::Kind::kRadarScan);
        ASSERT_EQ(scans.size(), static_cast<std::size_t>(kScans));
        for (int k = 0; k < kScans; ++k) ExpectExactScan(scans[k], k);  // scan 3: big-endian CDR
        const auto imu = OfKind(events, DatasetEvent::Kind::kImu);
        ASSERT_EQ(imu.size(), 20u);
        for (int n = 0; n < 20; ++n) {
            const int k = n / 4;
            const int j = n % 4;
            EXPECT_EQ(imu[n].imu.stamp_ns, ExpectedStamp(k) + 25000000LL * j);
            EXPECT_EQ(imu[n].imu.omega_imu_radps, Eigen::Vector3d(0.1 * k, 0.01 * j, -0.5));
            EXPECT_EQ(imu[n].imu.accel_imu_mps2, Eigen::Vector3d(1.0, 2.0 * j, 9.81));
        }
        const auto gt = OfKind(events, DatasetEvent::Kind::kGroundTruth);
        ASSERT_EQ(gt.size(), static_cast<std::size_t>(kScans));
        // (0, 0, 0.6, 0.8): a rotation about z by 2 atan2(0.6, 0.8).
        const Eigen::Matrix3d R =
            Eigen::AngleAxisd(2.0 * std::atan2(0.6, 0.8), Eigen::Vector3d::UnitZ()).matrix();
        for (int k = 0; k < kScans; ++k) {
            EXPECT_EQ(gt[k].stamp_ns, ExpectedStamp(k));
            EXPECT_EQ(gt[k].ground_truth.T_world_body.translation(),
                      Eigen::Vector3d(k, 2.0 * k, -k));
            EXPECT_LT((gt[k].ground_truth.T_world_body.linear() - R).norm(), 1e-12);
        }
        // The order of the recording: radar k (log +1 us), odometry (+2 us), IMU (from +0.5 us).
        for (std::size_t n = 1; n < events.size(); ++n) {
            if (events[n].kind == DatasetEvent::Kind::kImu &&
                events[n - 1].kind == DatasetEvent::Kind::kImu) {
                EXPECT_GT(events[n].stamp_ns, events[n - 1].stamp_ns);
            }
        }
    }
}

TEST_F(Rosbag2ReaderTest, PoseStampedGroundTruthThroughLoadGroundTruth) {
    const auto trajectory = LoadGroundTruth(Config("known.mcap", "/pose"));
    ASSERT_TRUE(trajectory.has_value());
    ASSERT_EQ(trajectory->poses().size(), static_cast<std::size_t>(kScans));
    EXPECT_EQ(trajectory->poses()[4].T_world_body.translation(), Eigen::Vector3d(4, 1, 2));
}

TEST_F(Rosbag2ReaderTest, ListTopicsCountsEveryTopic) {
    for (const char *bag : {"known.db3", "known.mcap", "split"}) {
        SCOPED_TRACE(bag);
        const auto topics = ListTopics(Config(bag));
        ASSERT_EQ(topics.size(), 4u);
        std::map<std::string, TopicSummary> by_name;
        for (const auto &t : topics) by_name[t.topic] = t;
        EXPECT_EQ(by_name["/imu"].messages, 20u);
        EXPECT_EQ(by_name["/imu"].type, "sensor_msgs/msg/Imu");
        EXPECT_EQ(by_name["/odom"].type, "nav_msgs/msg/Odometry");
        const TopicSummary &radar = by_name[kRadar];
        EXPECT_EQ(radar.messages, static_cast<std::size_t>(kScans));
        EXPECT_EQ(radar.type, "sensor_msgs/msg/PointCloud2");
        EXPECT_EQ(radar.first_ns, ExpectedStamp(0) + 1000);
        EXPECT_EQ(radar.last_ns, ExpectedStamp(4) + 1000);
        EXPECT_NE(radar.fields.find("doppler"), std::string::npos) << radar.fields;
    }
}

TEST_F(Rosbag2ReaderTest, CrcMismatchSkipsOnlyThatChunk) {
    const auto problems = ScansAndProblems("crc.mcap", {0, 1, 3, 4});
    ASSERT_EQ(problems.size(), 1u);
    EXPECT_NE(problems[0].find("crc.mcap: chunk at byte"), std::string::npos) << problems[0];
    EXPECT_NE(problems[0].find("CRC mismatch"), std::string::npos) << problems[0];
    EXPECT_NE(problems[0].find(std::string("1 on ") + kRadar), std::string::npos) << problems[0];
}

TEST_F(Rosbag2ReaderTest, UnsupportedCompressionSkipsOnlyThatChunk) {
    const auto problems = ScansAndProblems("bz2.mcap", {0, 2, 3, 4});
    ASSERT_EQ(problems.size(), 1u);
    EXPECT_NE(problems[0].find("bz2.mcap: chunk at byte"), std::string::npos) << problems[0];
    EXPECT_NE(problems[0].find("compression 'bz2' is not supported"), std::string::npos);
}

TEST_F(Rosbag2ReaderTest, TruncatedFilesKeepTheScansBeforeTheCut) {
    for (const char *bag : {"truncated_mcap.mcap", "truncated_db3.db3"}) {
        SCOPED_TRACE(bag);
        const auto events = testing::ReadAllEvents(Config(bag));
        const auto scans = OfKind(events, DatasetEvent::Kind::kRadarScan);
        EXPECT_GE(scans.size(), 1u);
        EXPECT_LT(scans.size(), static_cast<std::size_t>(kScans));
        for (std::size_t k = 0; k < scans.size(); ++k)
            ExpectExactScan(scans[k], static_cast<int>(k));
        const auto problems = OfKind(events, DatasetEvent::Kind::kBadScan);
        ASSERT_EQ(problems.size(), 1u);
        EXPECT_NE(problems[0].problem.find(bag), std::string::npos) << problems[0].problem;
        EXPECT_NE(problems[0].problem.find("truncated"), std::string::npos) << problems[0].problem;
    }
}

/// The message of the DatasetError that opening (and reading) the recording throws.
std::string OpenError(const DatasetConfig &config) {
    try {
        auto reader = OpenDataset(config);
        DatasetEvent e;
        while (reader->Next(e)) {
        }
    } catch (const DatasetError &e) {
        return e.what();
    }
    return "";
}

TEST_F(Rosbag2ReaderTest, FatalProblemsNameFileTopicAndCause) {
    const std::string type = OpenError(Config("laserscan.db3"));
    EXPECT_NE(type.find("laserscan.db3: topic /hugin_raf_1/radar_data has type "
                        "sensor_msgs/msg/LaserScan, expected sensor_msgs/msg/PointCloud2"),
              std::string::npos)
        << type;
    const std::string meta = OpenError(Config("nometa"));
    EXPECT_NE(meta.find("nometa: a folder without metadata.yaml"), std::string::npos) << meta;
    const std::string missing = OpenError(Config("known.mcap", "/no_such_topic"));
    EXPECT_NE(missing.find("topic '/no_such_topic' is not in the bag (rosbag.ground_truth_topic)"),
              std::string::npos)
        << missing;
    const auto text = dir_ / "text.mcap";
    std::ofstream(text) << "not a recording\n";
    const std::string magic = OpenError(Config("text.mcap"));
    EXPECT_NE(magic.find("text.mcap: unrecognised first bytes"), std::string::npos) << magic;
}

TEST_F(Rosbag2ReaderTest, CommandLinePathsResolveToTheRecording) {
    for (const char *bag : {"known.db3", "known.mcap", "split"}) {
        const DatasetConfig config = ResolveDataset((dir_ / bag).string());
        EXPECT_EQ(config.reader, ReaderKind::kRosbag);
        EXPECT_EQ(config.rosbag.path, (dir_ / bag).string());
        EXPECT_EQ(OfKind(testing::ReadAllEvents(config), DatasetEvent::Kind::kRadarScan).size(),
                  5u);
    }
    EXPECT_THROW((void)ResolveDataset((dir_ / "nometa").string()), ConfigError);
}

}  // namespace
}  // namespace dorado::io
