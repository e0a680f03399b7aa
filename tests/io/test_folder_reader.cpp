// Folders of scan files: View-of-Delft-like .bin, ColoRadar-like .bin, and PCD, with timestamps.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>

#include "dorado/io/dataset.hpp"
#include "dorado/io/folder_layout.hpp"
#include "dorado/testing/dataset_events.hpp"

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
    void WriteTimes(std::size_t n) {
        std::ofstream out(dir_ / "times.txt");
        for (std::size_t i = 0; i < n; ++i) out << 0.1 * static_cast<double>(i) << "\n";
    }
    // `points` rows of `columns` float32 values; value (row, col) = row * 100 + col.
    void WriteRows(const std::string &name, std::size_t points, std::size_t columns) {
        std::vector<std::vector<float>> rows(points, std::vector<float>(columns));
        for (std::size_t r = 0; r < points; ++r)
            for (std::size_t c = 0; c < columns; ++c) rows[r][c] = static_cast<float>(100 * r + c);
        WriteBin(name, rows);
    }
    static std::string Name(std::size_t i) {
        char name[16];
        std::snprintf(name, sizeof(name), "%05zu.bin", i);
        return name;
    }
    // x, y, z, doppler and then ignored columns, `columns` in all (>= 4).
    DatasetConfig ColumnsConfig(std::size_t columns) {
        std::vector<std::string> names = {"x", "y", "z", "v"};
        names.resize(columns, "_");
        DatasetConfig config = Config(names);
        config.fields.power = "";
        config.fields.doppler = "v";
        return config;
    }

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
    const auto events = testing::ReadAllEvents(config);
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
    const auto events = testing::ReadAllEvents(config);
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
    const auto events = testing::ReadAllEvents(Config({}, ".pcd"));
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

// RadarScenes-like files of 6 float32 columns (95..412 points) described with 5: refused, even
// the scans whose point count is a multiple of 5 (which would read with shifted columns).
TEST_F(FolderReaderTest, SixColumnFilesDescribedWithFiveAreRefusedWithTheCountThatFits) {
    std::mt19937 rng(33);
    std::uniform_int_distribution<std::size_t> points(95, 412);
    std::vector<std::size_t> counts;
    for (std::size_t i = 0; i < 40; ++i) {
        counts.push_back(points(rng));
        WriteRows(Name(i), counts.back(), 6);
    }
    WriteTimes(counts.size());
    try {
        (void)OpenDataset(ColumnsConfig(5));
        FAIL() << "a folder of 6-column files read as 5 columns";
    } catch (const DatasetError &e) {
        const std::string what = e.what();
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        EXPECT_NE(what.find((dir_ / "scans").string() + ": folder.columns has 5 entries"),
                  std::string::npos)
            << what;
        EXPECT_NE(what.find("every file fits 6"), std::string::npos) << what;
    }
    const auto problem = CheckFolderLayout(ColumnsConfig(5));
    ASSERT_TRUE(problem.has_value());
    EXPECT_EQ(problem->fix.rfind("folder.columns has 5 entries; every file fits 6", 0), 0u)
        << problem->fix;
    EXPECT_FALSE(CheckFolderLayout(ColumnsConfig(6)).has_value());
    const auto events = testing::ReadAllEvents(ColumnsConfig(6));
    ASSERT_EQ(events.size(), counts.size());
    for (std::size_t i = 0; i < counts.size(); ++i) {
        ASSERT_EQ(events[i].kind, DatasetEvent::Kind::kRadarScan) << events[i].problem;
        ASSERT_EQ(events[i].scan.size(), static_cast<Eigen::Index>(counts[i]));
        EXPECT_EQ(events[i].scan.doppler_mps[1], 103.0);  // row 1, column 3
    }
}

// The rule: at most one file in a hundred (at least one) may not fit; it is a counted skip.
TEST_F(FolderReaderTest, AFewOddFilesAreCountedSkipsMoreRefuseTheFolder) {
    for (std::size_t i = 0; i < 150; ++i) WriteRows(Name(i), 10 + i % 7, 5);
    WriteBin(Name(150), {{1, 2}});  // 8 bytes
    WriteTimes(151);
    const auto events = testing::ReadAllEvents(ColumnsConfig(5));
    ASSERT_EQ(events.size(), 151u);
    EXPECT_EQ(events[150].kind, DatasetEvent::Kind::kBadScan);
    EXPECT_NE(events[150].problem.find("not a multiple of 5"), std::string::npos);
    WriteBin(Name(151), {{1, 2, 3}});  // a second odd file: 2 > max(1, 152 / 100)
    WriteTimes(152);
    EXPECT_THROW((void)OpenDataset(ColumnsConfig(5)), DatasetError);
    const auto problem = CheckFolderLayout(ColumnsConfig(5));
    ASSERT_TRUE(problem.has_value());
    EXPECT_NE(problem->message.find("2 of 152"), std::string::npos) << problem->message;
    EXPECT_NE(problem->fix.find("no column count fits every file"), std::string::npos)
        << problem->fix;
}

// Property: for random true and configured column counts and random point counts, the reader
// either refuses the folder or uses only scans whose layout the sizes verify (at most the allowed
// misfits, each of them skipped), and it never refuses the true layout. The truth is computed
// here from the generator's counts, not from the files.
TEST_F(FolderReaderTest, NeverUsesAScanWhoseLayoutTheSizesCannotVerify) {
    std::mt19937 rng(20261203);
    std::uniform_int_distribution<std::size_t> true_cols(1, 12), configured(4, 9), nfiles(1, 30),
        npoints(0, 40);
    std::size_t refused = 0, accepted_wrong = 0;
    for (int trial = 0; trial < 150; ++trial) {
        fs::remove_all(dir_ / "scans");
        fs::create_directories(dir_ / "scans");
        const std::size_t t = true_cols(rng), c = configured(rng), n = nfiles(rng);
        const std::size_t allowed = std::max<std::size_t>(1, n / 100);  // the documented rule
        std::vector<std::size_t> points(n);
        std::size_t misfits = 0;
        for (std::size_t i = 0; i < n; ++i) {
            points[i] = npoints(rng);
            WriteRows(Name(i), points[i], t);
            misfits += (points[i] * t) % c != 0;
        }
        WriteTimes(n);
        // The rule's second half: any misfit refuses when another count of 3 or more fits every
        // (non-empty) file.
        bool other_fits = false;
        const bool all_empty =
            std::all_of(points.begin(), points.end(), [&](std::size_t p) { return p * t == 0; });
        for (std::size_t k = 3; k <= 32 && !all_empty; ++k)
            other_fits = other_fits ||
                         (k != c && std::all_of(points.begin(), points.end(),
                                                [&](std::size_t p) { return (p * t) % k == 0; }));
        const bool must_refuse = misfits > allowed || (misfits > 0 && other_fits);
        const std::string where = "trial " + std::to_string(trial) + ": " + std::to_string(n) +
                                  " files of " + std::to_string(t) + " columns read as " +
                                  std::to_string(c);
        std::vector<DatasetEvent> events;
        try {
            events = testing::ReadAllEvents(ColumnsConfig(c));
        } catch (const DatasetError &e) {
            ++refused;
            EXPECT_NE(t, c) << where << ": the true layout refused: " << e.what();
            EXPECT_TRUE(must_refuse) << where;
            if (t >= 2 && std::string(e.what()).find("every file fits") != std::string::npos)
                EXPECT_NE(std::string(e.what()).find(std::to_string(t)), std::string::npos)
                    << where << ": " << e.what();
            continue;
        }
        EXPECT_FALSE(must_refuse) << where;
        ASSERT_EQ(events.size(), n) << where;
        accepted_wrong += t != c;
        for (std::size_t i = 0; i < n; ++i) {
            const bool fits = (points[i] * t) % c == 0;
            EXPECT_EQ(events[i].kind == DatasetEvent::Kind::kRadarScan, fits) << where << ", " << i;
            if (fits)
                EXPECT_EQ(static_cast<std::size_t>(events[i].scan.size()) * c, points[i] * t)
                    << where;
        }
    }
    EXPECT_GT(refused, 20u);  // the wrong layouts that sizes can tell were told
    std::printf("refused %zu, accepted a wrong layout the sizes cannot tell %zu of 150\n", refused,
                accepted_wrong);
}

// PCD folders: a field of the field map missing in most files refuses the folder; in one file of
// ten it is that file's counted skip.
TEST_F(FolderReaderTest, PcdFieldMissingInManyFilesRefusesTheFolder) {
    const auto write_pcd = [this](int i, bool with_doppler) {
        std::ofstream(dir_ / "scans" / (std::to_string(i) + ".pcd"))
            << "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z power" << (with_doppler ? " doppler" : "")
            << "\nSIZE 4 4 4 4" << (with_doppler ? " 4" : "") << "\nTYPE F F F F"
            << (with_doppler ? " F" : "") << "\nCOUNT 1 1 1 1" << (with_doppler ? " 1" : "")
            << "\nWIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n1 2 2 30"
            << (with_doppler ? " -0.75" : "") << "\n";
    };
    for (int i = 0; i < 10; ++i) write_pcd(i, i != 4);
    WriteTimes(10);
    const auto events = testing::ReadAllEvents(Config({}, ".pcd"));
    ASSERT_EQ(events.size(), 10u);
    EXPECT_EQ(events[4].kind, DatasetEvent::Kind::kBadScan);
    EXPECT_EQ(events[5].kind, DatasetEvent::Kind::kRadarScan);
    for (int i = 0; i < 10; i += 2) write_pcd(i, false);
    try {
        (void)OpenDataset(Config({}, ".pcd"));
        FAIL() << "PCD files without the Doppler field read";
    } catch (const DatasetError &e) {
        EXPECT_NE(std::string(e.what()).find(
                      "fields.doppler names 'doppler', missing in 5 of 10 *.pcd files (e.g. 0.pcd: "
                      "x y z power)"),
                  std::string::npos)
            << e.what();
    }
}

// The .bin layouts the shipped configs name (ColoRadar 5, View-of-Delft 7 columns): files of one
// column more are refused, files of the named count are read.
TEST_F(FolderReaderTest, ShippedBinLayoutsRefuseFilesOfAnotherWidth) {
    for (const char *name : {"coloradar.yaml", "view_of_delft.yaml"}) {
        DatasetConfig config =
            LoadDatasetConfig(std::string(DORADO_SOURCE_DIR) + "/configs/" + name);
        ASSERT_EQ(config.reader, ReaderKind::kFolder) << name;
        config.folder.scans_dir = (dir_ / "scans").string();
        config.folder.timestamps_file = (dir_ / "times.txt").string();
        const std::size_t columns = config.folder.columns.size();
        for (std::size_t width : {columns + 1, columns}) {
            fs::remove_all(dir_ / "scans");
            fs::create_directories(dir_ / "scans");
            for (std::size_t i = 0; i < 12; ++i) WriteRows(Name(i), 3 + i, width);
            WriteTimes(12);
            if (width != columns) {
                EXPECT_THROW((void)OpenDataset(config), DatasetError) << name;
                const auto problem = CheckFolderLayout(config);
                ASSERT_TRUE(problem.has_value()) << name;
                EXPECT_NE(problem->fix.find("every file fits " + std::to_string(width)),
                          std::string::npos)
                    << problem->fix;
            } else {
                EXPECT_EQ(testing::ReadAllEvents(config).size(), 12u) << name;
            }
        }
    }
}

// Several radars (the radars: list) read as one stream in time order, each event naming its
// radar; a radar on another clock is refused by name.
TEST_F(FolderReaderTest, RadarsAreMergedInTimeOrderAndAnotherClockIsRefused) {
    const auto write_radar = [&](const std::string &name, const std::vector<double> &times) {
        fs::create_directories(dir_ / name);
        std::ofstream stamps(dir_ / (name + ".txt"));
        for (std::size_t i = 0; i < times.size(); ++i) {
            stamps << times[i] << "\n";
            std::ofstream out(dir_ / name / Name(i), std::ios::binary);
            const float row[4] = {10.0F, 1.0F, 0.0F, -2.0F};
            out.write(reinterpret_cast<const char *>(row), sizeof(row));
        }
    };
    write_radar("front", {0.10, 0.20, 0.30});
    write_radar("left", {0.05, 0.15, 0.25, 0.35});
    DatasetConfig config = ColumnsConfig(4);
    const auto radar = [&](const std::string &name) {
        RadarStream r;
        r.name = name;
        r.scans_dir = (dir_ / name).string();
        r.timestamps_file = (dir_ / (name + ".txt")).string();
        return r;
    };
    for (const std::string name : {"front", "left"}) config.radars.push_back(radar(name));
    config.folder.scans_dir = config.radars[0].scans_dir;
    config.folder.timestamps_file = config.radars[0].timestamps_file;
    auto reader = OpenRadars(config);
    std::vector<std::pair<int64_t, std::size_t>> order;
    DatasetEvent e;
    while (reader->Next(e)) {
        ASSERT_EQ(e.kind, DatasetEvent::Kind::kRadarScan);
        order.emplace_back(e.stamp_ns, e.radar);
    }
    const std::vector<std::pair<int64_t, std::size_t>> expected = {
        {50000000, 1},  {100000000, 0}, {150000000, 1}, {200000000, 0},
        {250000000, 1}, {300000000, 0}, {350000000, 1}};
    EXPECT_EQ(order, expected);

    write_radar("late", {1000.0, 1000.1});  // seconds since boot beside 0.1 s: another clock
    config.radars.push_back(radar("late"));
    try {
        (void)OpenRadars(config);
        FAIL() << "a radar on another clock was merged";
    } catch (const DatasetError &error) {
        EXPECT_NE(std::string(error.what()).find("radar 'late'"), std::string::npos)
            << error.what();
    }
}

}  // namespace
}  // namespace dorado::io
