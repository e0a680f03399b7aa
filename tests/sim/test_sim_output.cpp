// `dorado simulate`'s files end to end: the dataset description loads with the io reader, the bag
// streams back with stamps that line up with the ground truth and the true twists, Doppler in the
// bag follows eq. (1), output is reproducible for a seed, and Python's rosbag reads the bag.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>

#include "dorado/core/time.hpp"
#include "dorado/io/dataset.hpp"
#include "dorado/io/dataset_config.hpp"
#include "dorado/io/trajectory_io.hpp"
#include "dorado/sim/sequence_config.hpp"
#include "dorado/sim/simulator.hpp"

namespace dorado::sim {
namespace {

namespace fs = std::filesystem;

SequenceConfig ShortSequence(uint64_t seed) {
    SequenceConfig config = LoadSequenceConfig(FindSequenceFile("seq07"));
    config.duration_s = 6.0;
    config.seed = seed;
    return config;
}

std::string ReadAll(const fs::path &path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class SimulatedDataset : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        dir_ = fs::temp_directory_path() / ("dorado_sim_test_" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        result_ =
            new SimulationResult(SimulateToDirectory(ShortSequence(7), (dir_ / "a").string()));
    }
    static void TearDownTestSuite() {
        delete result_;
        fs::remove_all(dir_);
    }
    static inline fs::path dir_;
    static inline SimulationResult *result_ = nullptr;
};

TEST_F(SimulatedDataset, DescriptionLoadsWithTheDatasetReader) {
    const io::DatasetConfig config = io::LoadDatasetConfig((dir_ / "a" / "dataset.yaml").string());
    EXPECT_EQ(config.reader, io::ReaderKind::kRosbag);
    EXPECT_TRUE(fs::exists(config.rosbag.path)) << config.rosbag.path;
    EXPECT_TRUE(fs::exists(config.ground_truth.path)) << config.ground_truth.path;
    EXPECT_EQ(config.rosbag.radar_topic, "/hugin_raf_1/radar_data");
    const SequenceConfig seq = ShortSequence(7);
    EXPECT_TRUE(config.extrinsics.T_base_radar.isApprox(seq.radar.mount.Transform(), 1e-12));
    EXPECT_TRUE(config.extrinsics.T_base_imu.isApprox(seq.imu.mount.Transform(), 1e-12));
    EXPECT_DOUBLE_EQ(config.vehicle.half_wheelbase_m, seq.vehicle.half_wheelbase_m);
    EXPECT_NEAR(config.extrinsics.T_base_radar.translation().x(), 0.72, 1e-12);  // s_x
    // The radar's datasheet, as the simulator draws its noise and aliasing.
    EXPECT_DOUBLE_EQ(config.radar.range_sigma_m, seq.radar.range_sigma_m);
    EXPECT_DOUBLE_EQ(config.radar.azimuth_sigma_deg, seq.radar.azimuth_sigma_deg);
    EXPECT_DOUBLE_EQ(config.radar.elevation_sigma_deg, seq.radar.elevation_sigma_deg);
    EXPECT_DOUBLE_EQ(config.radar.doppler_unambiguous_mps, seq.radar.doppler_unambiguous_mps);
}

TEST_F(SimulatedDataset, BagStreamsBackWithAlignedStamps) {
    const io::DatasetConfig config = io::ResolveDataset((dir_ / "a").string());
    auto reader = io::OpenDataset(config);
    io::DatasetEvent event;
    std::vector<int64_t> radar_stamps, gt_stamps;
    std::size_t imu = 0;
    int64_t last = INT64_MIN;
    double sum_r2 = 0.0;
    std::size_t n_points = 0;
    while (reader->Next(event)) {
        ASSERT_GE(event.stamp_ns, last) << "events out of time order";
        last = event.stamp_ns;
        if (event.kind == io::DatasetEvent::Kind::kRadarScan) {
            const std::size_t k = radar_stamps.size();
            ASSERT_LT(k, result_->twists.size());
            radar_stamps.push_back(event.stamp_ns);
            // eq. (1) on what the reader decoded, with the true twist: the median residual of a
            // scan is ~0 (most points are static), whatever the noise.
            std::vector<double> residuals;
            const Eigen::Matrix3Xd d = UnitDirections(event.scan);
            for (Eigen::Index i = 0; i < event.scan.size(); ++i) {
                residuals.push_back(event.scan.doppler_mps[i] +
                                    d.col(i).dot(result_->twists[k].v_radar));
            }
            std::nth_element(residuals.begin(), residuals.begin() + residuals.size() / 2,
                             residuals.end());
            sum_r2 += residuals[residuals.size() / 2] * residuals[residuals.size() / 2];
            n_points += residuals.size();
        } else if (event.kind == io::DatasetEvent::Kind::kImu) {
            ++imu;
        } else if (event.kind == io::DatasetEvent::Kind::kGroundTruth) {
            gt_stamps.push_back(event.stamp_ns);
        } else {
            FAIL() << "bad scan: " << event.problem;
        }
    }
    ASSERT_EQ(radar_stamps.size(), result_->twists.size());
    for (std::size_t k = 0; k < radar_stamps.size(); ++k)
        EXPECT_EQ(radar_stamps[k], result_->twists[k].stamp_ns);
    EXPECT_EQ(radar_stamps.size(), result_->stats.scans);
    EXPECT_NEAR(static_cast<double>(n_points) / radar_stamps.size(),
                result_->stats.points_per_scan_mean, 1e-6);
    EXPECT_LT(std::sqrt(sum_r2 / radar_stamps.size()), 0.02);
    EXPECT_EQ(imu, result_->stats.imu_samples);
    EXPECT_NEAR(static_cast<double>(imu), 6.0 * 200 + 1, 1.0);

    // The ground truth: 10 Hz, the same stamps in the bag and in ground_truth.tum, spanning the
    // radar scans (so every scan can be interpolated).
    const Trajectory tum = io::ReadTum((dir_ / "a" / "ground_truth.tum").string());
    ASSERT_EQ(tum.size(), gt_stamps.size());
    for (std::size_t k = 0; k < tum.size(); ++k) {
        EXPECT_EQ(tum[k].stamp_ns, gt_stamps[k]);
        if (k > 0) {
            EXPECT_EQ(gt_stamps[k] - gt_stamps[k - 1], 100'000'000);
        }
    }
    EXPECT_LE(gt_stamps.front(), radar_stamps.front());
    EXPECT_GE(gt_stamps.back(), radar_stamps.back());
    // ~66.7 ms between scans at 15 Hz.
    EXPECT_NEAR(NanosToSeconds(radar_stamps[1] - radar_stamps[0]), 1.0 / 15.0, 1e-9);
}

TEST_F(SimulatedDataset, GroundTruthHasSmallCorrelatedError) {
    const Trajectory &gt = result_->ground_truth;
    const Trajectory &truth = result_->true_trajectory;
    ASSERT_EQ(gt.size(), truth.size());
    double max_error = 0.0, sum_step = 0.0;
    Eigen::Vector3d previous = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < gt.size(); ++k) {
        const Eigen::Vector3d e =
            gt[k].T_world_body.translation() - truth[k].T_world_body.translation();
        max_error = std::max(max_error, e.norm());
        if (k > 0) sum_step += (e - previous).norm();
        previous = e;
    }
    EXPECT_GT(max_error, 0.005);  // cm-level, not exact
    EXPECT_LT(max_error, 0.15);
    // Correlated: it changes far less from one pose to the next than its size.
    EXPECT_LT(sum_step / (gt.size() - 1), 0.5 * max_error);
}

TEST_F(SimulatedDataset, TrueTrajectoryFileIsExactAndMovesAsTheTrueTwists) {
    const Trajectory exact = io::ReadTum((dir_ / "a" / "true_trajectory.tum").string());
    const Trajectory &gt = result_->ground_truth;
    ASSERT_EQ(exact.size(), gt.size());
    double max_to_reported = 0.0;
    for (std::size_t k = 0; k < exact.size(); ++k) {
        EXPECT_EQ(exact[k].stamp_ns, gt[k].stamp_ns);
        EXPECT_TRUE(exact[k].T_world_body.isApprox(result_->true_trajectory[k].T_world_body, 1e-6));
        max_to_reported = std::max(
            max_to_reported,
            (exact[k].T_world_body.translation() - gt[k].T_world_body.translation()).norm());
    }
    EXPECT_GT(max_to_reported, 0.005);  // not the reported (mapper-like) ground truth
    // Independent of the reported ground truth: the displacement over each 0.1 s interval, seen in
    // the body frame at its start, is the true twist's velocity integrated over it (radar-rate
    // samples, nearest to the interval's middle; a ~1 m/s vehicle, so the bound is a few mm).
    std::size_t checked = 0;
    for (std::size_t k = 0; k + 1 < exact.size(); ++k) {
        const int64_t t_mid = (exact[k].stamp_ns + exact[k + 1].stamp_ns) / 2;
        const TrueTwist *nearest = nullptr;
        for (const TrueTwist &tw : result_->twists)
            if (nearest == nullptr ||
                std::llabs(tw.stamp_ns - t_mid) < std::llabs(nearest->stamp_ns - t_mid))
                nearest = &tw;
        if (nearest == nullptr || std::llabs(nearest->stamp_ns - t_mid) > 20'000'000) continue;
        const Eigen::Isometry3d step = exact[k].T_world_body.inverse() * exact[k + 1].T_world_body;
        const double dt = NanosToSeconds(exact[k + 1].stamp_ns - exact[k].stamp_ns);
        EXPECT_LT((step.translation() - nearest->twist_base.v_base_mps * dt).norm(), 0.01)
            << "pose " << k;
        ++checked;
    }
    EXPECT_GT(checked, exact.size() / 2);
}

TEST_F(SimulatedDataset, ReproducibleForASeed) {
    const SimulationResult again = SimulateToDirectory(ShortSequence(7), (dir_ / "b").string());
    const SimulationResult other = SimulateToDirectory(ShortSequence(8), (dir_ / "c").string());
    for (const char *file : {"data.bag", "ground_truth.tum", "true_trajectory.tum",
                             "true_twist.csv", "dataset.yaml"}) {
        EXPECT_EQ(ReadAll(dir_ / "a" / file), ReadAll(dir_ / "b" / file)) << file;
    }
    EXPECT_NE(ReadAll(dir_ / "a" / "data.bag"), ReadAll(dir_ / "c" / "data.bag"));
    EXPECT_EQ(again.stats.points_per_scan_mean, result_->stats.points_per_scan_mean);
}

TEST_F(SimulatedDataset, PythonRosbagReadsTheBag) {
    const fs::path script = dir_ / "read.py";
    std::ofstream(script)
        << "import rosbag, sys\n"
           "b = rosbag.Bag(sys.argv[1])\n"
           "n = {t: 0 for t in ('/hugin_raf_1/radar_data', '/imu/data', '/ground_truth/odom')}\n"
           "pts = 0\n"
           "for topic, msg, t in b.read_messages():\n"
           "    n[topic] += 1\n"
           "    if topic == '/hugin_raf_1/radar_data':\n"
           "        assert [f.name for f in msg.fields] == "
           "['x','y','z','range','elevation','azimuth','power','doppler']\n"
           "        assert msg.point_step == 32 and len(msg.data) == 32 * msg.width\n"
           "        pts += msg.width\n"
           "print(n['/hugin_raf_1/radar_data'], n['/imu/data'], n['/ground_truth/odom'], pts)\n";
    const fs::path out = dir_ / "read.txt";
    const std::string command = std::string(DORADO_SYSTEM_PYTHON) + " " + script.string() + " " +
                                (dir_ / "a" / "data.bag").string() + " > " + out.string();
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    std::istringstream line(ReadAll(out));
    std::size_t scans = 0, imu = 0, gt = 0, points = 0;
    line >> scans >> imu >> gt >> points;
    EXPECT_EQ(scans, result_->stats.scans);
    EXPECT_EQ(imu, result_->stats.imu_samples);
    EXPECT_EQ(gt, result_->stats.ground_truth_poses);
    EXPECT_NEAR(static_cast<double>(points) / scans, result_->stats.points_per_scan_mean, 1e-6);
}

TEST(SequenceConfig, BuiltInSequencesLoadAndBadKeysAreNamed) {
    for (const char *name :
         {"seq04", "seq05", "seq06", "seq07", "seq08", "seq11", "car_urban", "side_mount"}) {
        EXPECT_NO_THROW((void)LoadSequenceConfig(FindSequenceFile(name))) << name;
    }
    const fs::path bad = fs::temp_directory_path() / "dorado_bad_sequence.yaml";
    std::ofstream(bad) << "duration_s: 10\nradar:\n  rate_hz: 15\n  max_rnage_m: 80\n";
    try {
        (void)LoadSequenceConfig(bad.string());
        FAIL() << "an unknown key was accepted";
    } catch (const SequenceConfigError &e) {
        EXPECT_NE(std::string(e.what()).find("radar.max_rnage_m"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(bad.string()), std::string::npos) << e.what();
    }
    std::ofstream(bad) << "duration_s: -3\n";
    EXPECT_THROW((void)LoadSequenceConfig(bad.string()), SequenceConfigError);
    EXPECT_THROW((void)FindSequenceFile("no_such_sequence"), SequenceConfigError);
    fs::remove(bad);
}

}  // namespace
}  // namespace dorado::sim
