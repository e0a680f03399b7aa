// `dorado odometry`, `dorado map` and `dorado info` end to end on damaged recordings written by the
// real ROS tools (make_fault_bag.py): NaN scans, an empty scan, a stamp going backwards, a 10 s gap
// without scans or IMU, PointCloud2 layouts that lie, and configured topics that are empty or
// absent. The scan indices and the truth (a constant twist) are the generator's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "dorado/core/lie.hpp"

namespace {

namespace fs = std::filesystem;

// make_fault_bag.py
constexpr int kScans = 90, kGoodScans = 30;
// All-NaN scans 20 and 35 and the empty scan 25 keep a pose; these three are skipped:
constexpr int kBackwardScan = 30, kPointStepScan = 40, kRowStepScan = 45;
constexpr int kGapAfter = 59;
constexpr double kRate = 10.0, kGapS = 10.0, kSpeed = 2.0, kYawRate = 0.15;
constexpr int64_t kT0Ns = 1700000000LL * 1000000000LL;
const std::string kRadarTopic = "/hugin_raf_1/radar_data";

double ScanTime(int k) {  // seconds after the first scan
    return k / kRate + (k > kGapAfter ? kGapS : 0.0);
}

// The truth: the constant twist from the first scan on, through the gap too.
Eigen::Isometry3d TruePose(double t_s) {
    dorado::Vector6d xi;
    xi << kSpeed, 0, 0, 0, 0, kYawRate;
    return dorado::ExpSE3(xi * t_s);
}

/// One line of trajectory.tum, parsed here rather than through dorado's reader so that the test
/// sees exactly what was written.
struct TumPose {
    int64_t stamp_ns = 0;
    double values[7] = {};  // tx ty tz qx qy qz qw
    [[nodiscard]] Eigen::Vector3d position() const { return {values[0], values[1], values[2]}; }
};

std::vector<TumPose> ReadTumText(const fs::path &path) {
    std::ifstream in(path);
    EXPECT_TRUE(in) << path;
    std::vector<TumPose> poses;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream tokens(line);
        std::string stamp;
        tokens >> stamp;
        const auto dot = stamp.find('.');
        TumPose pose;
        pose.stamp_ns = std::stoll(stamp.substr(0, dot)) * 1000000000LL;
        if (dot != std::string::npos) {
            const std::string fraction = (stamp.substr(dot + 1) + "000000000").substr(0, 9);
            pose.stamp_ns += std::stoll(fraction);
        }
        for (double &v : pose.values) {
            std::string token;
            tokens >> token;
            v = std::strtod(token.c_str(), nullptr);  // "nan" and "inf" parse as themselves
        }
        poses.push_back(pose);
    }
    return poses;
}

class CmdFaults : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        dir_ = fs::path(::testing::TempDir()) / ("dorado_cmd_faults_" + std::to_string(::getpid()));
        const std::string cmd = std::string(DORADO_SYSTEM_PYTHON) + " " + DORADO_SOURCE_DIR +
                                "/tests/apps/make_fault_bag.py " + dir_.string();
        ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    }
    static void TearDownTestSuite() { fs::remove_all(dir_); }

    struct Result {
        int code = -1;
        std::string out, err;
    };
    // Runs dorado with the arguments; stdout and stderr are captured.
    static Result Dorado(const std::string &args) {
        const std::string out = (dir_ / "stdout.txt").string(),
                          err = (dir_ / "stderr.txt").string();
        const std::string cmd =
            std::string(DORADO_BINARY) + " " + args + " > " + out + " 2> " + err;
        const int status = std::system(cmd.c_str());
        auto slurp = [](const std::string &path) {
            std::ifstream in(path);
            std::stringstream ss;
            ss << in.rdbuf();
            return ss.str();
        };
        return {WEXITSTATUS(status), slurp(out), slurp(err)};
    }
    static std::string Faults() { return (dir_ / "faults" / "dataset.yaml").string(); }
    static std::string EmptyTopics() { return (dir_ / "empty_topics" / "dataset.yaml").string(); }
    static nlohmann::json Summary(const fs::path &out) {
        return nlohmann::json::parse(std::ifstream(out / "summary.json"));
    }
    static fs::path dir_;
};
fs::path CmdFaults::dir_;

// The stamps dorado must write for the faults bag: every scan but the one whose stamp goes back and
// the two it cannot decode. Scans without a finite point still get a pose (the odometry integrates
// its last valid twist over them, the mapper uses the prior): they have a real stamp.
std::vector<int> ScansWithAPose() {
    std::vector<int> scans;
    for (int k = 0; k < kScans; ++k)
        if (k != kBackwardScan && k != kPointStepScan && k != kRowStepScan) scans.push_back(k);
    return scans;
}

// Finite poses with unit quaternions, strictly increasing stamps, one per scan in `scans`.
void ExpectSaneTrajectory(const std::vector<TumPose> &poses, const std::vector<int> &scans,
                          const std::string &what) {
    ASSERT_EQ(poses.size(), scans.size()) << what;
    for (std::size_t i = 0; i < poses.size(); ++i) {
        for (double v : poses[i].values) ASSERT_TRUE(std::isfinite(v)) << what << " pose " << i;
        const double q_norm = Eigen::Vector4d(poses[i].values + 3).norm();
        EXPECT_NEAR(q_norm, 1.0, 1e-6) << what << " pose " << i;
        if (i > 0) {
            ASSERT_GT(poses[i].stamp_ns, poses[i - 1].stamp_ns) << what << " pose " << i;
        }
        const int64_t expected =
            kT0Ns + static_cast<int64_t>(std::llround((0.05 + ScanTime(scans[i])) * 1e9));
        EXPECT_NEAR(static_cast<double>(poses[i].stamp_ns - expected), 0.0, 1e3)
            << what << " pose " << i << " should be scan " << scans[i];
    }
}

// summary.json's skips: scan 30 for its stamp, scans 40 and 45 for their layouts.
void ExpectSkipsReported(const nlohmann::json &summary, const std::string &what) {
    EXPECT_EQ(summary["scans"], kScans) << what;
    EXPECT_EQ(summary["scans_skipped"], 3) << what;
    EXPECT_EQ(summary["skip_reasons"],
              nlohmann::json({{"timestamp out of order", 1}, {"unreadable scan", 2}}))
        << what;
    const auto &skipped = summary["skipped"];
    ASSERT_EQ(skipped.size(), 3u) << what << skipped.dump();
    EXPECT_EQ(skipped[0]["scan"], kBackwardScan) << what;
    EXPECT_NE(skipped[0]["reason"].get<std::string>().find("not after the previous scan"),
              std::string::npos)
        << what << skipped.dump();
    EXPECT_EQ(skipped[1]["scan"], kPointStepScan) << what;
    EXPECT_NE(skipped[1]["reason"].get<std::string>().find(
                  "topic " + kRadarTopic +
                  ", scan 40: data holds 12800 bytes but 1 rows of 400 "
                  "points need 16000 (point_step 40, row_step 16000)"),
              std::string::npos)
        << what << skipped.dump();
    EXPECT_EQ(skipped[2]["scan"], kRowStepScan) << what;
    EXPECT_NE(skipped[2]["reason"].get<std::string>().find(
                  "scan 45: data holds 12800 bytes but 2 rows of 200 points need 16000 "
                  "(point_step 32, row_step 9600)"),
              std::string::npos)
        << what << skipped.dump();
}

// stderr names each skipped scan (and the topic of the undecodable ones) as it happens.
void ExpectSkipsAnnounced(const std::string &err, const std::string &what) {
    for (int k : {kBackwardScan, kPointStepScan, kRowStepScan})
        EXPECT_NE(err.find("dorado: warning: scan " + std::to_string(k) + ": "), std::string::npos)
            << what << ": scan " << k << "\n"
            << err;
    EXPECT_NE(err.find("topic " + kRadarTopic + ", scan 40"), std::string::npos) << what << err;
}

// Position error against the truth at the pose's time since the first pose: horizontal, and 3-D.
struct PositionError {
    double horizontal = 0.0, full = 0.0;
};
PositionError ErrorOf(const TumPose &pose, const TumPose &first) {
    const double t = (pose.stamp_ns - first.stamp_ns) * 1e-9;
    const Eigen::Vector3d error = pose.position() - TruePose(t).translation();
    return {error.head<2>().norm(), error.norm()};
}

const TumPose &PoseOfScan(const std::vector<TumPose> &poses, int scan) {
    const auto scans = ScansWithAPose();
    const auto it = std::find(scans.begin(), scans.end(), scan);
    return poses.at(static_cast<std::size_t>(it - scans.begin()));
}

// The scans used despite a fault: 20, 25 and 35 without a finite point, 60 after the gap.
void ExpectWarnings(const nlohmann::json &summary, const std::string &err,
                    const std::string &no_points_consequence, const std::string &gap_consequence,
                    const std::string &what) {
    EXPECT_EQ(summary["warnings"], nlohmann::json({{"gap", 1}, {"no finite points", 3}})) << what;
    EXPECT_EQ(summary["nonfinite_points_removed"], 800) << what;
    const std::string expected[] = {
        "scan 20: 400 points with NaN/Inf values removed, none left: " + no_points_consequence,
        "scan 25: no points: " + no_points_consequence,
        "scan 35: 400 points with NaN/Inf values removed, none left: " + no_points_consequence,
        "scan 60: 10.10 s after the previous scan (ordinary interval 0.10 s); " + gap_consequence};
    const auto &warned = summary["warned"];
    ASSERT_EQ(warned.size(), 4u) << what << warned.dump();
    for (std::size_t i = 0; i < 4; ++i) {
        const std::string text = "scan " + std::to_string(warned[i]["scan"].get<int>()) + ": " +
                                 warned[i]["warning"].get<std::string>();
        EXPECT_EQ(text, expected[i]) << what;
        EXPECT_NE(err.find("dorado: warning: " + expected[i] + "\n"), std::string::npos)
            << what << "\n"
            << err;
    }
}

TEST_F(CmdFaults, OdometrySkipsWhatItCannotUseAndIntegratesOverTheGap) {
    const fs::path out = dir_ / "odometry";
    const Result r = Dorado("odometry " + Faults() + " --out " + out.string());
    ASSERT_EQ(r.code, 0) << r.err;
    const auto poses = ReadTumText(out / "trajectory.tum");
    ExpectSaneTrajectory(poses, ScansWithAPose(), "odometry");
    const auto summary = Summary(out);
    ExpectSkipsReported(summary, "odometry");
    ExpectSkipsAnnounced(r.err, "odometry");
    EXPECT_EQ(summary["scans_used"], kScans - 3);
    // The NaN and the empty scans have no finite point: the last valid twist is integrated over
    // them, and they are counted and named.
    EXPECT_EQ(summary["scans_with_fallback_twist"], 3);
    EXPECT_EQ(summary["invalid_velocity_reasons"], nlohmann::json({{"empty scan", 3}}));
    ExpectWarnings(summary, r.err, "empty scan; used the last valid twist",
                   "integrated this scan's twist over it", "odometry");

    // The gap: the vehicle kept its twist for 10.1 s, and the odometry integrates the twist of the
    // scan after the gap over the real interval (20 m of arc, 1.5 rad of yaw), so the pose stays
    // on the truth. Ignoring the gap, or integrating a zero twist over it, would be ~20 m off.
    // The single-scan pitch rate (sigma ~0.05 rad/s on this radar geometry) is integrated over the
    // 10 s too: here ~0.1 rad of pitch and 0.85 m of height, hence the loose 3-D bound.
    const auto before = ErrorOf(PoseOfScan(poses, kGapAfter), poses[0]);
    const auto after = ErrorOf(PoseOfScan(poses, kGapAfter + 1), poses[0]);
    const auto last = ErrorOf(poses.back(), poses[0]);
    std::printf(
        "odometry position error (horizontal / 3-D): before the gap %.3f / %.3f m, after "
        "%.3f / %.3f m, last %.3f / %.3f m\n",
        before.horizontal, before.full, after.horizontal, after.full, last.horizontal, last.full);
    EXPECT_LT(before.full, 0.15);
    EXPECT_LT(after.horizontal, 0.2);
    EXPECT_LT(last.horizontal, 0.2);
    EXPECT_LT(after.full, 1.5);
    EXPECT_LT(last.full, 1.5);
}

TEST_F(CmdFaults, MapWithDopplerAndConstantVelocityPriors) {
    for (const std::string prior : {"doppler", "constvel"}) {
        const fs::path out = dir_ / ("map_" + prior);
        const Result r = Dorado("map " + Faults() + " --prior " + prior + " --out " + out.string());
        ASSERT_EQ(r.code, 0) << prior << "\n" << r.err;
        const auto poses = ReadTumText(out / "trajectory.tum");
        ExpectSaneTrajectory(poses, ScansWithAPose(), "map " + prior);
        const auto summary = Summary(out);
        ExpectSkipsReported(summary, "map " + prior);
        ExpectSkipsAnnounced(r.err, "map " + prior);
        EXPECT_EQ(summary["scans_registered"], kScans - 3) << prior;
        // Without a point the Doppler prior has no velocity either: constvel stands in.
        ExpectWarnings(summary, r.err, "pose from the constvel prior",
                       "the " + prior + " prior spans it", "map " + prior);
        EXPECT_EQ(summary["fallback_reasons"]["too few points"], 3) << prior;
        // Counted by cause (for the doppler prior, the ego-velocity's) under a key without digits.
        if (prior == "doppler")
            EXPECT_EQ(summary["prior_substitutions_constvel"]["doppler: empty scan"], 3);
        else
            EXPECT_EQ(summary["prior_substitutions_constvel"], nlohmann::json::object());
        // Registration against the landmarks seen before the gap pulls the pose back onto the
        // truth after it, in height too.
        const auto after = ErrorOf(PoseOfScan(poses, kGapAfter + 1), poses[0]);
        const auto last = ErrorOf(poses.back(), poses[0]);
        std::printf("map --prior %s position error (3-D): after the gap %.3f m, last %.3f m\n",
                    prior.c_str(), after.full, last.full);
        EXPECT_LT(after.full, 0.3) << prior;
        EXPECT_LT(last.full, 0.3) << prior;
    }
}

TEST_F(CmdFaults, InfoListsEveryProblem) {
    const Result r = Dorado("info " + Faults());
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string &out = r.out;
    for (const std::string expected : {
             "radar scans: 88 read, 2 unreadable",  // 90 messages, 40 and 45 undecodable
             "radar time not increasing: 1\n    - scan 30: -50.0 ms after the previous scan\n",
             "gaps longer than 5 scan intervals: 1\n    - 10.10 s without a scan before scan 60\n",
             "scans with NaN/Inf points (removed): 2\n    - scan 20: 400 points\n"
             "    - scan 35: 400 points\n",
             // 25, and 20 and 35 once their NaN points are removed
             "empty scans: 3\n    - scan 20\n    - scan 25\n    - scan 35\n",
             "unreadable scans: 2\n",
             "scan 40: data holds 12800 bytes but 1 rows of 400 points need 16000",
             "scan 45: data holds 12800 bytes but 2 rows of 200 points need 16000",
         })
        EXPECT_NE(out.find(expected), std::string::npos) << expected << "\n" << out;
    EXPECT_EQ(out.find("configured topics without messages"), std::string::npos) << out;
}

// The IMU and ground-truth topics are in the bag (connection records) with zero messages.
TEST_F(CmdFaults, ConfiguredTopicsWithoutMessages) {
    std::vector<int> all(kGoodScans);
    for (int k = 0; k < kGoodScans; ++k) all[k] = k;
    // What needs no IMU runs.
    const fs::path odometry = dir_ / "empty_topics_odometry", map = dir_ / "empty_topics_map";
    Result r = Dorado("odometry " + EmptyTopics() + " --out " + odometry.string());
    ASSERT_EQ(r.code, 0) << r.err;
    ExpectSaneTrajectory(ReadTumText(odometry / "trajectory.tum"), all, "odometry");
    r = Dorado("map " + EmptyTopics() + " --prior doppler --out " + map.string());
    ASSERT_EQ(r.code, 0) << r.err;
    ExpectSaneTrajectory(ReadTumText(map / "trajectory.tum"), all, "map");

    // What needs the IMU stops with one message naming the topic and the key.
    const std::string empty_imu =
        "dorado: error: " + (dir_ / "empty_topics" / "data.bag").string() +
        ": topic '/imu/data' (rosbag.imu_topic) has no messages; ";
    for (const std::string rotation : {"imu", "imu+doppler"}) {
        r = Dorado("odometry " + EmptyTopics() + " --method " + rotation + " --out " +
                   (dir_ / "x").string());
        EXPECT_EQ(r.code, 1) << rotation;
        EXPECT_EQ(r.err, empty_imu + "rotation from the IMU needs IMU samples\n") << rotation;
    }
    for (const std::string prior : {"imu", "imu+doppler"}) {
        r = Dorado("map " + EmptyTopics() + " --prior " + prior + " --out " +
                   (dir_ / "x").string());
        EXPECT_EQ(r.code, 1) << prior;
        EXPECT_EQ(r.err, empty_imu + "--prior " + prior + " needs IMU samples\n") << prior;
    }
    // s_x calibration needs the gyro: it says so, naming the topic and the key.
    r = Dorado("calibrate sx " + EmptyTopics() + " --out " + (dir_ / "sx.yaml").string());
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("(rosbag.imu_topic /imu/data): no gyro sample between the usable scans (0 "
                         "IMU samples)"),
              std::string::npos)
        << r.err;

    r = Dorado("info " + EmptyTopics());
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("/imu/data                        sensor_msgs/Imu                    0 "
                         "msgs"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("configured topics without messages: 2\n"
                         "    - /ground_truth/odom (rosbag.ground_truth_topic)\n"
                         "    - /imu/data (rosbag.imu_topic)\n"),
              std::string::npos)
        << r.out;
}

// imu_topic names a topic the bag does not have at all.
TEST_F(CmdFaults, AbsentTopicIsOneClearError) {
    const std::string expected = "dorado: error: " + (dir_ / "faults" / "data.bag").string() +
                                 ": topic '/imu/absent' is not in the bag (rosbag.imu_topic); "
                                 "topics:\n  " +
                                 kRadarTopic +
                                 " [sensor_msgs/PointCloud2]\n  /imu/data [sensor_msgs/Imu]; " +
                                 (dir_ / "x").string() + " was left as it was\n";
    const std::string yaml = (dir_ / "absent_topic.yaml").string();
    for (const std::string &command : {"odometry " + yaml + " --out " + (dir_ / "x").string(),
                                       "map " + yaml + " --out " + (dir_ / "x").string()}) {
        const Result r = Dorado(command);
        EXPECT_EQ(r.code, 1) << command;
        EXPECT_EQ(r.err, expected) << command;
    }
}

}  // namespace
