// The first hour's traps (issue 59), each tried as a new user would and answered with the right
// result or a clear refusal:
//   - a refused run leaves --out as it was: a field the recording does not have, a column count
//     that fits all files but one (nuScenes' fixed 125 points per scan);
//   - implausible results (Doppler beyond the radar's range, most scans falling back) exit 3 after
//     writing, unless --accept-implausible; a bare recording's assumed mount is said out loud;
//   - calibrate's window past the drive's end is refused;
//   - the small command-line items: an unknown command before --help, --radars and `config print`
//     typos, simulate --help's sequences, bench on Ctrl-C.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>

#include "dorado/testing/run_command.hpp"
#include "dorado/testing/scan_folder.hpp"

namespace {

namespace fs = std::filesystem;

std::string Slurp(const fs::path &path) {
    std::stringstream ss;
    ss << std::ifstream(path).rdbuf();
    return ss.str();
}

class FirstHour : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        dir_ = fs::path(::testing::TempDir()) / ("dorado_first_hour_" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        const Result sim = Dorado("simulate --sequence seq06 --duration 4 --out " + Sim().string());
        ASSERT_EQ(sim.code, 0) << sim.err;
    }
    static void TearDownTestSuite() { fs::remove_all(dir_); }

    using Result = dorado::testing::CommandResult;
    static Result Dorado(const std::string &args) {
        return dorado::testing::RunCommand(std::string(DORADO_BINARY) + " " + args, dir_);
    }
    static bool Has(const std::string &text, const std::string &part) {
        return dorado::testing::Contains(text, part);
    }
    static fs::path Sim() { return dir_ / "sim"; }
    // A command line refused with exit 1 and a message holding @p part.
    static void ExpectRefused(const std::string &args, const std::string &part) {
        const Result r = Dorado(args);
        EXPECT_EQ(r.code, 1) << args;
        EXPECT_TRUE(Has(r.err, part)) << args << ": " << r.err;
    }
    // The simulated description with one line replaced, beside it (its paths stay valid).
    static fs::path SimVariant(const std::string &name, const std::string &from,
                               const std::string &to) {
        const std::string text = Slurp(Sim() / "dataset.yaml");
        const std::string changed = std::regex_replace(text, std::regex(from), to);
        EXPECT_NE(changed, text) << from;
        const fs::path path = Sim() / name;
        std::ofstream(path) << changed;
        return path;
    }
    // A folder whose listing and contents are those of an earlier good run.
    static std::map<std::string, std::string> Contents(const fs::path &folder) {
        std::map<std::string, std::string> files;
        for (const auto &entry : fs::recursive_directory_iterator(folder))
            if (entry.is_regular_file()) files[entry.path().string()] = Slurp(entry.path());
        return files;
    }

    static fs::path dir_;
};

fs::path FirstHour::dir_;

TEST_F(FirstHour, AMisspeltFieldIsRefusedBeforeTheOutFolderIsTouched) {
    const fs::path out = dir_ / "good_run";
    const Result good = Dorado("odometry " + Sim().string() + " --out " + out.string());
    ASSERT_EQ(good.code, 0) << good.err;
    const auto before = Contents(out);
    const fs::path bad = SimVariant("pwr.yaml", "  power: power", "  power: pwr");
    const Result r = Dorado("odometry " + bad.string() + " --out " + out.string());
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_TRUE(Has(r.err, "pwr")) << r.err;
    EXPECT_TRUE(Has(r.err, "radar scans cannot be read")) << r.err;
    EXPECT_TRUE(Has(r.err, out.string() + " was left as it was")) << r.err;
    EXPECT_FALSE(Has(r.err, "held an earlier run's outputs")) << r.err;
    EXPECT_EQ(Contents(out), before);
    const Result map = Dorado("map " + bad.string() + " --out " + out.string());
    EXPECT_EQ(map.code, 1) << map.err;
    EXPECT_EQ(Contents(out), before);
}

// nuScenes' radars give 125 points per scan: 6-column files read as 5 columns fit in every file
// whose count is a multiple of 5, i.e. all but one. The count that fits every file is named.
TEST_F(FirstHour, AWrongColumnCountIsRefusedHoweverFewFilesShowIt) {
    const fs::path folder = dir_ / "fixed_count";
    fs::create_directories(folder / "scans");
    std::ofstream times(folder / "times.txt");
    for (int k = 0; k < 200; ++k) {  // times.txt is closed below, before the commands read it
        char name[32];
        std::snprintf(name, sizeof(name), "%05d.bin", k);
        std::ofstream scan(folder / "scans" / name, std::ios::binary);
        for (int i = 0; i < (k == 77 ? 124 : 125); ++i) {
            const float row[6] = {10.0f + i % 20, -5.0f + 0.1f * i, 0.0f, 5.0f, -1.0f, 11.0f};
            scan.write(reinterpret_cast<const char *>(row), sizeof(row));
        }
        times << 10.0 + 0.1 * k << "\n";
    }
    times.close();
    const fs::path description = folder / "five.yaml";
    std::ofstream(description)
        << "name: five\nreader: folder\nfolder:\n  scans_dir: scans\n  extension: .bin\n"
           "  timestamps_file: times.txt\n  columns: [x, y, z, rcs, v_r]\n"
           "fields: {x: x, y: y, z: z, range: \"\", azimuth: \"\", elevation: \"\", power: rcs, "
           "doppler: v_r}\nextrinsics:\n  T_base_radar: {translation_m: [3.6, 0, 0], "
           "rotation_rpy_deg: [0, 0, 0]}\n";
    const fs::path out = dir_ / "kept";
    fs::create_directories(out);
    std::ofstream(out / "trajectory.tum") << "earlier\n";
    for (const char *command : {"info", "odometry", "map"}) {
        const Result r = Dorado(std::string(command) + " " + description.string() +
                                (std::string(command) == "info" ? "" : " --out " + out.string()));
        EXPECT_EQ(r.code, 1) << command << ": " << r.out << r.err;
        EXPECT_TRUE(Has(r.out + r.err, "1 of 200")) << r.out << r.err;
        EXPECT_TRUE(Has(r.out + r.err, "every file fits 6")) << r.out << r.err;
    }
    EXPECT_EQ(Slurp(out / "trajectory.tum"), "earlier\n");
}

TEST_F(FirstHour, DopplerBeyondTheRadarsRangeExitsThreeUnlessAccepted) {
    // A car at ~9 m/s whose description says its radar wraps the Doppler at 4 m/s.
    const fs::path urban = dir_ / "urban";
    ASSERT_EQ(Dorado("simulate --sequence car_urban --duration 3 --out " + urban.string()).code, 0);
    const std::string text = Slurp(urban / "dataset.yaml");
    const fs::path narrow = urban / "narrow.yaml";
    std::ofstream(narrow) << std::regex_replace(
        text, std::regex("doppler_unambiguous_mps: [0-9.]+"), "doppler_unambiguous_mps: 4");
    const fs::path out = dir_ / "narrow";
    const Result r = Dorado("odometry " + narrow.string() + " --out " + out.string());
    EXPECT_EQ(r.code, 3) << r.err;
    EXPECT_TRUE(Has(r.err, "warning: implausible: ")) << r.err;
    EXPECT_TRUE(Has(r.err, "have a Doppler beyond +-4.0 m/s (radar.doppler_unambiguous_mps"))
        << r.err;
    EXPECT_TRUE(Has(r.err, "--accept-implausible")) << r.err;
    EXPECT_TRUE(fs::exists(out / "trajectory.tum"));  // written first
    const Result accepted =
        Dorado("odometry " + narrow.string() + " --accept-implausible --out " + out.string());
    EXPECT_EQ(accepted.code, 0) << accepted.err;
    const auto summary = nlohmann::json::parse(std::ifstream(out / "summary.json"));
    EXPECT_FALSE(summary["implausible"].empty());
    EXPECT_TRUE(summary["implausible_accepted"].get<bool>());
    // The plain description is plausible: exit 0 and an empty list.
    const Result plain = Dorado("odometry " + Sim().string() + " --out " + (dir_ / "p").string());
    EXPECT_EQ(plain.code, 0) << plain.err;
    EXPECT_TRUE(
        nlohmann::json::parse(std::ifstream(dir_ / "p" / "summary.json"))["implausible"].empty());
}

// The TI recording's radar-only map: 411 of 412 scans fell back, path 0 m, and it exited 0.
TEST_F(FirstHour, MostScansFallingBackExitsThree) {
    const fs::path ti = fs::path(DORADO_SOURCE_DIR) / ".." / "shared" / "data" / "real" /
                        "ti_mmwave_demo" / "ti_mmwave_rospkg_demo.bag";
    if (!fs::exists(ti)) GTEST_SKIP() << ti << " is absent";
    const fs::path source = DORADO_SOURCE_DIR;
    const Result r = Dorado("map " + (source / "configs" / "ti_mmwave.yaml").string() +
                            " --prior constvel --out " + (dir_ / "ti").string());
    EXPECT_EQ(r.code, 3) << r.err;
    EXPECT_TRUE(std::regex_search(r.err, std::regex("implausible: \\d+ of 412 scans fell back")))
        << r.err;
    EXPECT_TRUE(Has(r.err, "m long but the Doppler speed integrates to ")) << r.err;
}

TEST_F(FirstHour, ABareRecordingSaysWhatItAssumes) {
    const Result r = Dorado("odometry " + (Sim() / "data.bag").string() +
                            " --accept-implausible --out " + (dir_ / "bare").string());
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(Has(r.err, "has no dataset description: read as the paper's Hugin recording"))
        << r.err;
    EXPECT_TRUE(Has(r.err, "the radar mounted at translation_m [")) << r.err;
}

TEST_F(FirstHour, ACalibrationWindowPastTheDrivesEndIsRefused) {
    const fs::path out = dir_ / "sx.yaml";
    const Result r =
        Dorado("calibrate sx " + Sim().string() + " --from 10 --to 40 --out " + out.string());
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_TRUE(Has(r.err, "--from 10 s is past the drive's end")) << r.err;
    EXPECT_FALSE(fs::exists(out));
    ExpectRefused("calibrate sx " + Sim().string() + " --to 40 --out " + out.string(),
                  "--to 40 s is past the drive's end");
}

TEST_F(FirstHour, AnUnknownCommandBeforeHelpExitsOne) {
    const Result r = Dorado("nosuch --help");
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_TRUE(Has(r.err, "unknown command 'nosuch'")) << r.err;
    ExpectRefused("mapp --help", "did you mean 'map'?");
    ExpectRefused("config prnt --help", "did you mean 'print'?");
    EXPECT_EQ(Dorado("map --help").code, 0);
    EXPECT_EQ(Dorado("config print --help").code, 0);
}

TEST_F(FirstHour, ChoicesOfACommandSuggestTheClosest) {
    ExpectRefused("config print mapperr", "did you mean 'mapper'?");
    ExpectRefused("calibrate rotaton x.bag --out x.yaml", "did you mean 'rotation'?");

    // --radars on a two-radar folder.
    const fs::path folder = dir_ / "two";
    for (const char *radar : {"front", "left"}) {
        fs::create_directories(folder / radar);
        std::ofstream(folder / radar / "times.txt") << "10.0\n";
        std::ofstream scan(folder / radar / "00000.bin", std::ios::binary);
        const float row[5] = {10.0f, 1.0f, 0.0f, 5.0f, -1.0f};
        scan.write(reinterpret_cast<const char *>(row), sizeof(row));
    }
    std::ofstream(folder / "two.yaml")
        << "reader: folder\nfolder: {scans_dir: front, extension: .bin, timestamps_file: "
           "front/times.txt, columns: [x, y, z, rcs, v_r]}\n"
           "fields: {x: x, y: y, z: z, range: \"\", azimuth: \"\", elevation: \"\", power: rcs, "
           "doppler: v_r}\n"
           "radars:\n"
           "  - {name: front, scans_dir: front, timestamps_file: front/times.txt,\n"
           "     T_base_radar: {translation_m: [3.6, 0, 0], rotation_rpy_deg: [0, 0, 0]}}\n"
           "  - {name: left, scans_dir: left, timestamps_file: left/times.txt,\n"
           "     T_base_radar: {translation_m: [3.6, 0.8, 0], rotation_rpy_deg: [0, 0, 90]}}\n";
    const Result radars = Dorado("map " + (folder / "two.yaml").string() + " --radars fron --out " +
                                 (dir_ / "unused").string());
    EXPECT_EQ(radars.code, 1);
    EXPECT_TRUE(Has(radars.err, "did you mean 'front'?")) << radars.err;
    const Result all = Dorado("map " + (folder / "two.yaml").string() + " --radars al --out " +
                              (dir_ / "unused").string());
    EXPECT_TRUE(Has(all.err, "did you mean 'all'?")) << all.err;
}

TEST_F(FirstHour, SimulateHelpListsEveryBuiltInSequence) {
    const Result help = Dorado("simulate --help");
    ASSERT_EQ(help.code, 0);
    const Result error = Dorado("simulate --sequence nosuch --out " + (dir_ / "x").string());
    EXPECT_EQ(error.code, 1);
    std::size_t sequences = 0;
    for (const auto &entry :
         fs::directory_iterator(fs::path(DORADO_SOURCE_DIR) / "configs" / "sequences")) {
        if (entry.path().extension() != ".yaml") continue;
        const std::string name = entry.path().stem().string();
        EXPECT_TRUE(std::regex_search(help.out, std::regex("[ (]" + name + "[ )]"))) << name;
        EXPECT_TRUE(Has(error.err, name)) << name;
        ++sequences;
    }
    EXPECT_GE(sequences, 10u);
}

// Ctrl-C on `dorado bench`: the running runs end, none starts, it says what it kept, exit 130.
TEST_F(FirstHour, BenchSaysWhatItKeptOnCtrlC) {
    const fs::path out = dir_ / "bench", err = dir_ / "bench_err.txt", code = dir_ / "code.txt";
    const std::string config =
        (fs::path(DORADO_SOURCE_DIR) / "tests" / "workflow" / "tiny_benchmark.yaml").string();
    const std::string script =
        std::string(DORADO_BINARY) + " bench " + config + " --no-plot --jobs 1 --out " +
        out.string() + " 2> " + err.string() + " & p=$!; i=0; while [ ! -d " + out.string() +
        "/logs ] && [ $i -lt 600 ]; do sleep 0.05; i=$((i+1)); done; sleep 0.3; kill -INT $p; "
        "wait $p; echo $? > " +
        code.string();
    ASSERT_EQ(std::system(("sh -c '" + script + "'").c_str()), 0);
    EXPECT_EQ(Slurp(code), "130\n") << Slurp(err);
    const std::string text = Slurp(err);
    EXPECT_TRUE(Has(text, "bench interrupted (SIGINT): ")) << text;
    EXPECT_TRUE(Has(text, "runs finished, kept in " + fs::canonical(out).string() + "/runs"))
        << text;
    EXPECT_TRUE(Has(text, "the same command again runs the others")) << text;
}

}  // namespace
