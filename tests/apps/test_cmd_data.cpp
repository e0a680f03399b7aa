// Data wherever it lies, and checks that see everything, end to end through `dorado`:
//   - a shipped description copied anywhere runs from any working directory with --data DIR
//     (nuScenes scene-0061, skipped where ../shared/data/real is absent); without it, the error
//     names the key, the path as written and resolved, the folder it was taken from and --data;
//   - `dorado info` reads every radar of a radars: list (a real scan file truncated in a copy);
//   - a misspelt key is named before the key it leaves missing; a description without reader:
//     is asked for reader: by name;
//   - `dorado bench` with a missing input fails before its first run, naming it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "dorado/testing/scan_folder.hpp"

namespace {

namespace fs = std::filesystem;

const fs::path kSource = DORADO_SOURCE_DIR;
const fs::path kNuScenes = kSource / ".." / "shared" / "data" / "real" / "nuscenes_scene-0061";

std::string Slurp(const fs::path &path) {
    std::stringstream ss;
    ss << std::ifstream(path).rdbuf();
    return ss.str();
}

class CmdData : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = fs::path(::testing::TempDir()) /
               ("dorado_cmd_data_" + std::to_string(::getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_ / "cwd");
    }
    void TearDown() override { fs::remove_all(dir_); }

    struct Result {
        int code = -1;
        std::string out, err;
    };
    // Runs dorado in dir_/cwd (not the source tree, not the build tree).
    Result Dorado(const std::string &args) const {
        const std::string out = (dir_ / "stdout.txt").string(),
                          err = (dir_ / "stderr.txt").string();
        const std::string command = "cd '" + (dir_ / "cwd").string() + "' && " + DORADO_BINARY +
                                    " " + args + " > '" + out + "' 2> '" + err + "'";
        const int status = std::system(command.c_str());
        return {WEXITSTATUS(status), Slurp(out), Slurp(err)};
    }

    // A folder of two radars' scans (static points ahead, float32 x y z rcs v_r rows) and a
    // description of them, its paths relative to the description's folder.
    fs::path TwoRadarFolder(const std::string &second_radar_keys) const {
        for (const char *radar : {"front", "left"})
            dorado::testing::WriteScanFolder(dir_ / radar, 12, 20, [](int i, float *v) {
                v[0] = 10.0f + i, v[1] = -5.0f + 0.5f * i, v[2] = 0.0f, v[3] = 5.0f, v[4] = -1.0f;
            });
        const fs::path description = dir_ / "two.yaml";
        std::ofstream(description)
            << "name: two\n"
            << dorado::testing::kFrontFolderKeys
            << "radars:\n"
               "  - {name: front, scans_dir: front/scans, timestamps_file: front/times.txt,\n"
               "     T_base_radar: {translation_m: [1, 0, 0]}}\n"
               "  - {name: left, scans_dir: left/scans, "
            << second_radar_keys << "\n     T_base_radar: {translation_m: [0, 1, 0]}}\n";
        return description;
    }

    fs::path dir_;
};

TEST_F(CmdData, ShippedDescriptionCopiedAnywhereRunsWithData) {
    if (!fs::exists(kNuScenes / "radar_front" / "times.txt"))
        GTEST_SKIP() << "the nuScenes extract is absent (" << kNuScenes << ")";
    fs::create_directories(dir_ / "copy");
    fs::copy_file(kSource / "configs" / "nuscenes.yaml", dir_ / "copy" / "nuscenes.yaml");
    const std::string copy = (dir_ / "copy" / "nuscenes.yaml").string();

    const Result r = Dorado("map " + copy + " --data " + kNuScenes.string() +
                            " --prior doppler --out " + (dir_ / "map").string());
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_GT(fs::file_size(dir_ / "map" / "trajectory.tum"), 1000u);

    // Without --data the copy's data_dir: (relative to the copy) leads nowhere: the error says
    // which key, how its path was resolved, and how to change it; no output is written.
    const Result missing =
        Dorado("map " + copy + " --prior doppler --out " + (dir_ / "map2").string());
    EXPECT_EQ(missing.code, 1);
    for (const std::string expected :
         {"key 'folder.scans_dir'", "written radar_front/scans",
          "taken from the description's data_dir: ", "--data DIR", "absolute path"})
        EXPECT_NE(missing.err.find(expected), std::string::npos) << expected << "\n" << missing.err;
    EXPECT_FALSE(fs::exists(dir_ / "map2" / "trajectory.tum"));

    // --data naming a folder without the description's files: the same, taken from --data.
    const Result wrong = Dorado("info " + copy + " --data " + dir_.string());
    EXPECT_EQ(wrong.code, 1);
    EXPECT_NE(wrong.err.find("taken from --data " + dir_.string()), std::string::npos) << wrong.err;
}

TEST_F(CmdData, InfoReadsEveryRadarOfTheList) {
    if (!fs::exists(kNuScenes / "radar_left" / "times.txt"))
        GTEST_SKIP() << "the nuScenes extract is absent (" << kNuScenes << ")";
    fs::copy(kNuScenes, dir_ / "data", fs::copy_options::recursive);
    const std::string args = "info " + (kSource / "configs" / "nuscenes.yaml").string() +
                             " --data " + (dir_ / "data").string();
    Result r = Dorado(args);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("problems: none found"), std::string::npos) << r.out;

    // The left radar's scan 10 cut mid-row (the first radar's files are whole).
    const fs::path cut = dir_ / "data" / "radar_left" / "scans" / "00010.bin";
    fs::resize_file(cut, fs::file_size(cut) - 10);
    r = Dorado(args);
    EXPECT_EQ(r.code, 0) << r.err;  // reported and skipped, as the first radar's bad scans
    EXPECT_EQ(r.out.find("problems: none found"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("unreadable scans: 1\n    - left: "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("00010.bin"), std::string::npos) << r.out;
}

TEST_F(CmdData, MisspeltKeyIsNamedBeforeTheKeyItLeavesMissing) {
    const fs::path good = TwoRadarFolder("timestamps_file: left/times.txt,");
    EXPECT_EQ(Dorado("info " + good.string()).code, 0);
    const fs::path bad = TwoRadarFolder("timestamp_file: left/times.txt,");
    const Result r = Dorado("info " + bad.string());
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("radars[1].timestamp_file"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("is required"), std::string::npos) << r.err;
}

TEST_F(CmdData, DescriptionWithoutReaderIsAskedForReader) {
    const fs::path good = TwoRadarFolder("timestamps_file: left/times.txt,");
    std::string text = Slurp(good);
    text.erase(text.find("reader: folder\n"), std::string("reader: folder\n").size());
    std::ofstream(dir_ / "no_reader.yaml") << text;
    const Result r = Dorado("info " + (dir_ / "no_reader.yaml").string());
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("key 'reader': is required"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("add reader: folder"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("is not used by reader"), std::string::npos) << r.err;
}

TEST_F(CmdData, BenchWithAMissingInputFailsBeforeItsFirstRun) {
    const fs::path description = TwoRadarFolder("timestamps_file: left/times.txt,");
    std::ofstream(dir_ / "gt.tum") << "10.0 0 0 0 0 0 0 1\n11.1 1 0 0 0 0 0 1\n";
    std::ofstream(dir_ / "bench.yaml")
        << "jobs: 1\nodometry: [doppler]\nmap_priors: [none]\nsequences:\n"
           "  - {name: whole, dataset: two.yaml, ground_truth: gt.tum}\n"
           "  - {name: other, dataset: two.yaml, data: elsewhere, ground_truth: gt.tum}\n";
    fs::create_directories(dir_ / "elsewhere" / "front" / "scans");  // no times.txt, no left/
    const Result r = Dorado("bench " + (dir_ / "bench.yaml").string() + " --no-plot --out " +
                            (dir_ / "bench_out").string());
    EXPECT_EQ(r.code, 1);
    for (const std::string &expected : std::vector<std::string>{
             "sequence 'other'", "key 'folder.timestamps_file'", "front/times.txt",
             "taken from --data " + (dir_ / "elsewhere").string()})
        EXPECT_NE(r.err.find(expected), std::string::npos) << expected << "\n" << r.err;
    EXPECT_EQ(r.err.find(" runs ("), std::string::npos) << r.err;  // "bench: N runs (...)"
    EXPECT_FALSE(fs::exists(dir_ / "bench_out" / "runs")) << r.err;
}

}  // namespace
