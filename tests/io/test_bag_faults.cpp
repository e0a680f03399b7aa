// Fault injection on bags written by the real ROS tool: truncation at many offsets, flipped bytes,
// layouts that lie. The reader must report every fault clearly and never crash.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include "dorado/io/dataset.hpp"

namespace dorado::io {
namespace {

namespace fs = std::filesystem;

class BagFaultsTest : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        dir_ = fs::path(::testing::TempDir()) / ("dorado_faults_" + std::to_string(::getpid()));
        const std::string cmd = std::string(DORADO_SYSTEM_PYTHON) + " " + DORADO_SOURCE_DIR +
                                "/tests/io/make_test_bags.py " + dir_.string();
        ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
        std::ifstream in(dir_ / "many_chunks.bag", std::ios::binary);
        original_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        ASSERT_GT(original_.size(), 100000u);
    }
    static void TearDownTestSuite() { fs::remove_all(dir_); }

    static std::string WriteVariant(const std::vector<char> &bytes) {
        const std::string path = (dir_ / "variant.bag").string();
        std::ofstream(path, std::ios::binary | std::ios::trunc)
            .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        return path;
    }

    struct Outcome {
        bool open_error = false;
        std::size_t scans = 0, bad = 0;
        std::string first_problem;
    };

    static Outcome ReadAll(const std::string &path) {
        DatasetConfig config;
        config.rosbag.path = path;
        config.rosbag.imu_topic = "/imu/data";
        Outcome outcome;
        try {
            auto reader = OpenDataset(config);
            DatasetEvent event;
            while (reader->Next(event)) {
                if (event.kind == DatasetEvent::Kind::kRadarScan) {
                    ++outcome.scans;
                    EXPECT_TRUE(event.scan.xyz_radar.allFinite());
                    EXPECT_TRUE(event.scan.doppler_mps.allFinite());
                } else if (event.kind == DatasetEvent::Kind::kBadScan) {
                    ++outcome.bad;
                    if (outcome.first_problem.empty()) outcome.first_problem = event.problem;
                    EXPECT_NE(event.problem.find(path), std::string::npos) << event.problem;
                }
            }
        } catch (const DatasetError &e) {
            outcome.open_error = true;
            outcome.first_problem = e.what();
            EXPECT_NE(outcome.first_problem.find(path), std::string::npos) << e.what();
        }
        return outcome;
    }

    static fs::path dir_;
    static std::vector<char> original_;
};
fs::path BagFaultsTest::dir_;
std::vector<char> BagFaultsTest::original_;

TEST_F(BagFaultsTest, IntactBagReadsEveryScan) {
    const Outcome o = ReadAll((dir_ / "many_chunks.bag").string());
    EXPECT_FALSE(o.open_error) << o.first_problem;
    EXPECT_EQ(o.scans, 40u);
    EXPECT_EQ(o.bad, 0u);
}

TEST_F(BagFaultsTest, TruncatedAtFiftyOffsetsGivesAClearError) {
    std::mt19937 rng(2024);
    std::uniform_int_distribution<std::size_t> offset(0, original_.size() - 1);
    for (int trial = 0; trial < 50; ++trial) {
        const std::size_t cut = offset(rng);
        const Outcome o =
            ReadAll(WriteVariant(std::vector<char>(original_.begin(), original_.begin() + cut)));
        EXPECT_TRUE(o.open_error) << "cut at " << cut;
        EXPECT_NE(o.first_problem.find("rosbag reindex"), std::string::npos) << o.first_problem;
    }
}

TEST_F(BagFaultsTest, FlippedBytesNeverCrashAndAreReported) {
    std::mt19937 rng(99);
    // Damage the message data (past the bag header, before the index at the end).
    std::uniform_int_distribution<std::size_t> offset(4096, original_.size() * 3 / 4);
    std::size_t total_scans = 0, total_bad = 0, open_errors = 0;
    for (int trial = 0; trial < 50; ++trial) {
        std::vector<char> bytes = original_;
        for (int k = 0; k < 16; ++k) bytes[offset(rng)] ^= static_cast<char>(1 + rng() % 255);
        const Outcome o = ReadAll(WriteVariant(bytes));
        total_scans += o.scans;
        total_bad += o.bad;
        open_errors += o.open_error;
        if (!o.open_error) {
            EXPECT_LE(o.scans, 40u);
        }
    }
    std::printf(
        "flipped bytes, 50 trials: %zu scans read, %zu reported unreadable, %zu bags refused at "
        "open\n",
        total_scans, total_bad, open_errors);
    EXPECT_GT(total_scans, 0u) << "damage stays local: most scans survive";
}

}  // namespace
}  // namespace dorado::io
