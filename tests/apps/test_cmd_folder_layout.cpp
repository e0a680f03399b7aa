// End to end: a folder of 6-column float32 scans described with 5 columns. `dorado
// odometry` and `dorado map` stop with one line naming the folder, 5 and 6, exit 1 and write no
// file; `dorado info` prints the finding with its fix; the right count runs.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "dorado/testing/run_command.hpp"

namespace {

namespace fs = std::filesystem;

constexpr int kScans = 30;
constexpr double kSpeed = 2.0;  // m/s along the radar's x

class CmdFolderLayout : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        dir_ =
            fs::path(::testing::TempDir()) / ("dorado_folder_layout_" + std::to_string(::getpid()));
        fs::create_directories(dir_ / "scans");
        // Static points around a radar moving at kSpeed along x: x y z rcs v_r label rows, a
        // point count that is not a multiple of 5 in most scans.
        std::mt19937 rng(6);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        std::uniform_int_distribution<int> count(51, 79);
        std::ofstream times(dir_ / "times.txt");
        for (int k = 0; k < kScans; ++k) {
            char name[32];
            std::snprintf(name, sizeof(name), "%05d.bin", k);
            std::ofstream out(dir_ / "scans" / name, std::ios::binary);
            for (int i = count(rng); i > 0; --i) {
                const Eigen::Vector3d p(10.0 + 10.0 * u(rng), 15.0 * u(rng), 3.0 * u(rng));
                const float row[6] = {static_cast<float>(p.x()),
                                      static_cast<float>(p.y()),
                                      static_cast<float>(p.z()),
                                      10.0f,
                                      static_cast<float>(-kSpeed * p.x() / p.norm()),
                                      11.0f};
                out.write(reinterpret_cast<const char *>(row), sizeof(row));
            }
            times << 100.0 + 0.1 * k << "\n";
        }
    }
    static void TearDownTestSuite() { fs::remove_all(dir_); }

    static std::string Description(const std::string &columns) {
        const fs::path path = dir_ / ("dataset_" + std::to_string(columns.size()) + ".yaml");
        std::ofstream(path) << "name: layout\nreader: folder\nfolder:\n  scans_dir: scans\n"
                               "  extension: .bin\n  timestamps_file: times.txt\n  columns: ["
                            << columns
                            << "]\nfields: {x: x, y: y, z: z, range: \"\", azimuth: \"\", "
                               "elevation: \"\", power: rcs, doppler: v_r}\n"
                               "extrinsics:\n  T_base_radar: {translation_m: [1.0, 0.0, 0.0]}\n";
        return path.string();
    }
    static std::string Five() { return Description("x, y, z, rcs, v_r"); }
    static std::string Six() { return Description("x, y, z, rcs, v_r, label"); }

    using Result = dorado::testing::CommandResult;
    static Result Dorado(const std::string &args) {
        return dorado::testing::RunCommand(std::string(DORADO_BINARY) + " " + args, dir_);
    }
    // Regular files under `out` (the command may have made the folder itself).
    static int FilesIn(const fs::path &out) {
        int files = 0;
        if (!fs::exists(out)) return 0;
        for (const auto &e : fs::recursive_directory_iterator(out)) files += e.is_regular_file();
        return files;
    }

    static fs::path dir_;
};

fs::path CmdFolderLayout::dir_;

TEST_F(CmdFolderLayout, WrongColumnCountStopsEveryCommandWithOneLineAndNoOutput) {
    const std::string scans = (dir_ / "scans").string();
    for (const std::string command : {"odometry", "map"}) {
        const fs::path out = dir_ / ("out_five_" + command);
        const Result r = Dorado(command + " " + Five() + " --out " + out.string());
        EXPECT_EQ(r.code, 1) << command << "\n" << r.err;
        const std::string line = "dorado: error: " + scans + ": folder.columns has 5 entries";
        EXPECT_EQ(r.err.rfind(line, 0), 0u) << command << ":\n" << r.err;
        EXPECT_NE(r.err.find("every file fits 6"), std::string::npos) << r.err;
        EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line:\n" << r.err;
        EXPECT_EQ(FilesIn(out), 0) << command << " wrote into " << out;
    }
}

TEST_F(CmdFolderLayout, InfoPrintsTheFindingWithItsFix) {
    const Result r = Dorado("info " + Five());
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.out.find("problems:"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("fix: folder.columns has 5 entries; every file fits 6"), std::string::npos)
        << r.out;
    const Result good = Dorado("info " + Six());
    EXPECT_EQ(good.code, 0) << good.out << good.err;
    EXPECT_NE(good.out.find("radar scans: 30 read, 0 unreadable"), std::string::npos) << good.out;
}

TEST_F(CmdFolderLayout, TheRightCountRuns) {
    const fs::path out = dir_ / "out_six";
    const Result r = Dorado("odometry " + Six() + " --out " + out.string());
    ASSERT_EQ(r.code, 0) << r.err;
    std::ifstream tum(out / "trajectory.tum");
    int poses = 0;
    double last_x = 0.0;
    for (std::string line; std::getline(tum, line);) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream(line) >> last_x >> last_x;  // t, then x
        ++poses;
    }
    EXPECT_EQ(poses, kScans);
    // 29 intervals of 0.1 s at kSpeed: the Doppler alone gives the distance.
    EXPECT_NEAR(last_x, kSpeed * 0.1 * (kScans - 1), 0.05);
}

}  // namespace
