// Folders of scan files: View-of-Delft-like .bin, ColoRadar-like .bin, and PCD, with timestamps.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "dorado/io/dataset.hpp"

namespace dorado::io {
namespace {

namespace fs = std::filesystem;

class FolderReaderTest : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = fs::path(::testing::TempDir()) / ("dorado_folder_" + std::to_string(::getpid()));
        fs::create_directories(dir_ / "scans");
    }
    void TearDown() override { fs::remove_all(dir_); }

    void WriteBin(const std::string &name, const std::vector<std::vector<float>> &rows) {
        std::ofstream out(dir_ / "scans" / name, std::ios::binary);
        for (const auto &row : rows)
            out.write(reinterpret_cast<const char *>(row.data()), 4 * row.size());
    }
    void WriteTimes(const std::string &text) { std::ofstream(dir_ / "times.txt") << text; }

    DatasetConfig Config(std::vector<std::string> columns, const std::string &ext = ".bin") {
        DatasetConfig config;
        config.reader = ReaderKind::kFolder;
        config.folder.scans_dir = (dir_ / "scans").string();
        config.folder.extension = ext;
        config.folder.timestamps_file = (dir_ / "times.txt").string();
        config.folder.columns = std::move(columns);
        config.fields.range = config.fields.azimuth = config.fields.elevation = "";
        return config;
    }

    static std::vector<DatasetEvent> ReadAll(const DatasetConfig &config) {
        auto reader = OpenDataset(config);
        std::vector<DatasetEvent> events;
        DatasetEvent e;
        while (reader->Next(e)) events.push_back(e);
        return events;
    }

    fs::path dir_;
};

TEST_F(FolderReaderTest, ViewOfDelftSevenColumns) {
    WriteBin("00001.bin", {{1, 2, 3, -5, 0.5f, 0.1f, 0}, {4, 0, 0, 7, -1.25f, 0, 0}});
    WriteBin("00002.bin", {{0, 3, 4, 2, 2.0f, 0, 0}});
    WriteBin("00003.bin", {{1, 1}});  // 8 bytes: not a multiple of 7 columns
    WriteTimes("1690000000.1\n1690000000.2\n1690000000.3\n");
    DatasetConfig config = Config({"x", "y", "z", "RCS", "v_r", "v_r_compensated", "time"});
    config.fields.power = "RCS";
    config.fields.doppler = "v_r";
    const auto events = ReadAll(config);
    ASSERT_EQ(events.size(), 3u);
    ASSERT_EQ(events[0].kind, DatasetEvent::Kind::kRadarScan) << events[0].problem;
    EXPECT_EQ(events[0].stamp_ns, 1690000000100000000LL);
    ASSERT_EQ(events[0].scan.size(), 2);
    EXPECT_EQ(events[0].scan.power_db[0], -5.0);
    EXPECT_EQ(events[0].scan.doppler_mps[1], -1.25);
    EXPECT_EQ(events[1].scan.range_m[0], 5.0) << "range derived from xyz";
    EXPECT_EQ(events[2].kind, DatasetEvent::Kind::kBadScan);
    EXPECT_NE(events[2].problem.find("00003.bin (scan 2)"), std::string::npos) << events[2].problem;
    EXPECT_NE(events[2].problem.find("not a multiple of 7"), std::string::npos)
        << events[2].problem;
}

TEST_F(FolderReaderTest, ColoRadarFiveColumnsWithIgnoredColumn) {
    WriteBin("a.bin", {{1, 0, 0, 9, -0.5f}});
    WriteTimes("10.5\n");
    DatasetConfig config = Config({"x", "y", "z", "_", "v_r"});
    config.fields.power = "";
    config.fields.doppler = "v_r";
    const auto events = ReadAll(config);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_FALSE(events[0].scan.has_power);
    EXPECT_EQ(events[0].scan.power_db[0], 0.0);
    EXPECT_EQ(events[0].scan.doppler_mps[0], -0.5);
}

TEST_F(FolderReaderTest, PcdFilesWithTheSameFieldMap) {
    std::ofstream(dir_ / "scans" / "0.pcd")
        << "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z power doppler\n"
           "SIZE 4 4 4 4 8\nTYPE F F F F F\nCOUNT 1 1 1 1 1\nWIDTH 2\nHEIGHT 1\n"
           "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n"
           "1 2 2 30 -0.75\n0 0 -2 15 0.125\n";
    WriteTimes("0.0\n");
    const auto events = ReadAll(Config({}, ".pcd"));
    ASSERT_EQ(events.size(), 1u);
    ASSERT_EQ(events[0].kind, DatasetEvent::Kind::kRadarScan) << events[0].problem;
    EXPECT_EQ(events[0].scan.size(), 2);
    EXPECT_EQ(events[0].scan.range_m[0], 3.0);
    EXPECT_EQ(events[0].scan.power_db[1], 15.0);
    EXPECT_EQ(events[0].scan.doppler_mps[0], -0.75);
}

TEST_F(FolderReaderTest, TimestampCountMismatchAndBadLinesAreErrors) {
    WriteBin("a.bin", {{1, 0, 0, 9, -0.5f}});
    WriteTimes("1.0\n2.0\n");
    EXPECT_THROW((void)OpenDataset(Config({"x", "y", "z", "power", "doppler"})), DatasetError);
    WriteTimes("one\n");
    try {
        (void)OpenDataset(Config({"x", "y", "z", "power", "doppler"}));
        FAIL();
    } catch (const DatasetError &e) {
        EXPECT_NE(std::string(e.what()).find("times.txt:1: not a time"), std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace dorado::io
