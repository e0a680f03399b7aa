// The native readers with every radar: nuScenes' five RADAR_* channels and RadarScenes' four
// sensors, read from devkit-layout copies of the shared drives (make_devkit_copies.py), against the
// same drives read from the converted extract folders (reader folder, a radars: list): the same
// radars and mounts, the same scans at the same times, the same IMU samples. And the command line's
// scene / sequence choice, and the messages on bad input.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "dorado/io/dataset.hpp"

namespace dorado::io {
namespace {

namespace fs = std::filesystem;

// ../shared/data/real next to the checkout, or DORADO_SHARED_REAL (a checkout elsewhere).
const fs::path kShared = std::getenv("DORADO_SHARED_REAL")
                             ? fs::path(std::getenv("DORADO_SHARED_REAL"))
                             : fs::path(DORADO_SOURCE_DIR) / ".." / "shared" / "data" / "real";

std::vector<DatasetEvent> ReadRadars(const DatasetConfig &config) {
    auto reader = OpenRadars(config);
    std::vector<DatasetEvent> events;
    DatasetEvent event;
    while (reader->Next(event)) events.push_back(event);
    return events;
}

template <typename F>
std::string ConfigErrorOf(F f) {
    try {
        f();
    } catch (const ConfigError &e) {
        return e.what();
    }
    return "";
}

// The text contains every part.
void ExpectMentions(const std::string &text, const std::vector<std::string> &parts) {
    for (const std::string &part : parts)
        EXPECT_NE(text.find(part), std::string::npos) << "'" << part << "' not in: " << text;
}

class NativeRadars : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        if (!fs::exists(kShared / "nuscenes_scene-0061" / "mounts.txt") ||
            !fs::exists(kShared / "radarscenes_105_radar4" / "times.txt"))
            return;
        dir_ = fs::path(::testing::TempDir()) / ("dorado_devkit_" + std::to_string(::getpid()));
        const std::string cmd = std::string(DORADO_SYSTEM_PYTHON) + " " + DORADO_SOURCE_DIR +
                                "/tests/io/make_devkit_copies.py " + kShared.string() + " " +
                                dir_.string() + " > /dev/null";
        ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    }
    static void TearDownTestSuite() {
        if (!dir_.empty()) fs::remove_all(dir_);
    }
    void SetUp() override {
        if (dir_.empty())
            GTEST_SKIP() << "the shared real drives are absent (" << kShared.string()
                         << "; DORADO_SHARED_REAL names another place)";
    }

    static std::string Path(const std::string &name) { return (dir_ / name).string(); }
    static std::string Yaml(const std::string &name, const std::string &body) {
        std::ofstream(dir_ / (name + ".yaml")) << body;
        return Path(name + ".yaml");
    }

    // Both descriptions list the same radars with the same mounts, and read the same events.
    static void ExpectSameDrive(const std::string &set, std::size_t radars) {
        const DatasetConfig native = LoadDatasetConfig(Path(set + "_native.yaml"));
        const DatasetConfig extracts = LoadDatasetConfig(Path(set + "_extracts.yaml"));
        ASSERT_EQ(native.radars.size(), radars);
        ASSERT_EQ(extracts.radars.size(), radars);
        for (std::size_t k = 0; k < radars; ++k) {
            EXPECT_EQ(native.radars[k].name, extracts.radars[k].name);
            EXPECT_TRUE(
                native.radars[k].T_base_radar.isApprox(extracts.radars[k].T_base_radar, 1e-9))
                << native.radars[k].name;
        }
        EXPECT_TRUE(native.extrinsics.T_base_radar.isApprox(extracts.radars[0].T_base_radar, 1e-9));
        const auto a = ReadRadars(native), b = ReadRadars(extracts);
        ASSERT_EQ(a.size(), b.size());
        std::vector<std::size_t> scans(radars, 0);
        for (std::size_t e = 0; e < a.size(); ++e) {
            ASSERT_EQ(a[e].kind, b[e].kind) << "event " << e << ": " << a[e].problem;
            ASSERT_EQ(a[e].stamp_ns, b[e].stamp_ns) << "event " << e;
            if (a[e].kind == DatasetEvent::Kind::kImu) {
                EXPECT_EQ(a[e].imu.omega_imu_radps, b[e].imu.omega_imu_radps);
                continue;
            }
            ASSERT_EQ(a[e].kind, DatasetEvent::Kind::kRadarScan) << a[e].problem;
            ASSERT_EQ(a[e].radar, b[e].radar) << "event " << e;
            EXPECT_EQ(a[e].scan_index, scans[a[e].radar]++);
            EXPECT_EQ(a[e].scan_index, b[e].scan_index);
            const RadarScan &p = a[e].scan, &q = b[e].scan;
            ASSERT_EQ(p.size(), q.size()) << "event " << e;
            for (Eigen::Index i = 0; i < p.size(); ++i) {
                const double range = q.xyz_radar.col(i).norm();
                // float32 range/azimuth (RadarScenes) or vx, vy (nuScenes) in between
                EXPECT_NEAR((p.xyz_radar.col(i) - q.xyz_radar.col(i)).norm(), 0.0,
                            1e-6 * range + 1e-6)
                    << e << "/" << i;
                EXPECT_NEAR(p.doppler_mps[i], q.doppler_mps[i], 1e-5) << e << "/" << i;
                EXPECT_EQ(p.power_db[i], q.power_db[i]);
            }
        }
        for (std::size_t k = 0; k < radars; ++k) EXPECT_GT(scans[k], 200u) << k;
    }

    static fs::path dir_;
};

fs::path NativeRadars::dir_;

TEST_F(NativeRadars, NuScenesFiveChannelsAreTheExtracts) {
    ExpectSameDrive("nuscenes", 5);
    const DatasetConfig native = LoadDatasetConfig(Path("nuscenes_native.yaml"));
    EXPECT_EQ(native.radars.front().nuscenes_channel, "RADAR_FRONT");
    EXPECT_EQ(fs::path(native.imu.path), dir_ / "nuscenes" / "can_bus" / "scene-0061_ms_imu.json");
}

TEST_F(NativeRadars, RadarScenesFourSensorsAreTheExtracts) {
    ExpectSameDrive("radarscenes", 4);
    EXPECT_EQ(LoadDatasetConfig(Path("radarscenes_native.yaml")).radars[2].radarscenes_sensor_id,
              3);
}

TEST_F(NativeRadars, TheReferenceIsTheEgoPosesAndTheOdometry) {
    // nuScenes: ground_truth.tum's poses are among the scene's ego poses (LIDAR_TOP's).
    const auto ego = LoadGroundTruth(LoadDatasetConfig(Path("nuscenes_native.yaml")));
    ASSERT_TRUE(ego.has_value());
    std::ifstream gt(kShared / "nuscenes_scene-0061" / "ground_truth.tum");
    int rows = 0;
    for (double t, x, y, z, qx, qy, qz, qw; gt >> t >> x >> y >> z >> qx >> qy >> qz >> qw;) {
        const auto T = ego->Interpolate(static_cast<int64_t>(std::llround(t * 1e6)) * 1000);
        ASSERT_TRUE(T.has_value()) << t;
        EXPECT_NEAR((T->translation() - Eigen::Vector3d(x, y, z)).norm(), 0.0, 1e-9) << t;
        ++rows;
    }
    EXPECT_GT(rows, 900);
    // RadarScenes: the odometry table holds radar 3's reference poses (float32 x_seq, y_seq).
    const auto odometry = LoadGroundTruth(LoadDatasetConfig(Path("radarscenes_native.yaml")));
    ASSERT_TRUE(odometry.has_value());
    std::ifstream ref(kShared / "radarscenes_105_radar3" / "reference.tum");
    for (double t, x, y, z, qx, qy, qz, qw; ref >> t >> x >> y >> z >> qx >> qy >> qz >> qw;) {
        const auto T = odometry->Interpolate(static_cast<int64_t>(std::llround(t * 1e6)) * 1000);
        ASSERT_TRUE(T.has_value()) << t;
        EXPECT_NEAR((T->translation() - Eigen::Vector3d(x, y, 0.0)).norm(), 0.0, 2e-4) << t;
    }
}

// The description written back (as `dorado simulate` and the round trips write it) has no radars:
// key (these readers refuse one) and reads the same radars again from the files.
TEST_F(NativeRadars, EveryRadarRoundTripsThroughYaml) {
    for (const std::string set : {"nuscenes", "radarscenes"}) {
        const DatasetConfig native = LoadDatasetConfig(Path(set + "_native.yaml"));
        const std::string text = DatasetConfigToYaml(native);
        EXPECT_EQ(text.find("\nradars:"), std::string::npos) << text;
        const DatasetConfig back = LoadDatasetConfig(Yaml(set + "_back", text));
        ASSERT_EQ(back.radars.size(), native.radars.size()) << set;
        for (std::size_t k = 0; k < back.radars.size(); ++k) {
            EXPECT_EQ(back.radars[k].name, native.radars[k].name);
            EXPECT_TRUE(back.radars[k].T_base_radar.isApprox(native.radars[k].T_base_radar, 1e-12));
        }
        EXPECT_EQ(back.imu.path, native.imu.path);
    }
}

TEST_F(NativeRadars, OneRadarByNameIsThatRadarAlone) {
    const DatasetConfig native = LoadDatasetConfig(Path("nuscenes_native.yaml"));
    const DatasetConfig extracts = LoadDatasetConfig(Path("nuscenes_extracts.yaml"));
    const DatasetConfig left = ForRadar(native, 3);  // RADAR_BACK_LEFT
    EXPECT_TRUE(left.radars.empty());
    EXPECT_TRUE(left.extrinsics.T_base_radar.isApprox(extracts.radars[3].T_base_radar, 1e-9));
    DatasetConfig one = ForRadar(extracts, 3);
    one.imu.path = left.imu.path;
    const auto a = ReadRadars(left), b = ReadRadars(one);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t e = 0; e < a.size(); ++e) {
        EXPECT_EQ(a[e].stamp_ns, b[e].stamp_ns);
        EXPECT_EQ(a[e].scan.size(), b[e].scan.size());
        EXPECT_EQ(a[e].scan.frame_id,
                  a[e].kind == DatasetEvent::Kind::kRadarScan ? "RADAR_BACK_LEFT" : "");
    }
    // A channel given in the description: that radar alone, no radars: list.
    const DatasetConfig front = LoadDatasetConfig(
        Yaml("nu_front",
             "reader: nuscenes\nnuscenes: {dataroot: nuscenes, version: v1.0-mini, scene: "
             "scene-0061, channel: RADAR_FRONT}\n"));
    EXPECT_TRUE(front.radars.empty());
    EXPECT_TRUE(front.extrinsics.T_base_radar.isApprox(extracts.radars[0].T_base_radar, 1e-9));
}

TEST_F(NativeRadars, TheCommandLineChoosesTheSceneAndTheSequence) {
    DatasetChoice scene;
    scene.scene = "scene-0103";  // the front radar's first 40 sweeps, 1000 s later
    const DatasetConfig later = LoadDatasetConfig(Path("nuscenes_native.yaml"), scene);
    EXPECT_EQ(later.nuscenes.scene, "scene-0103");
    ASSERT_EQ(later.radars.size(), 1u);  // the one channel with sweeps there
    std::size_t scans = 0;
    for (const DatasetEvent &e : ReadRadars(later)) {
        if (e.kind != DatasetEvent::Kind::kRadarScan) continue;
        EXPECT_EQ(e.scan.frame_id, "RADAR_FRONT");
        EXPECT_GT(e.stamp_ns, int64_t{1000} * 1000000000);
        ++scans;
    }
    EXPECT_EQ(scans, 40u);
    DatasetChoice sequence;
    sequence.sequence = "106";  // the first 100 scenes of sequence_105
    const DatasetConfig short_drive = ResolveDataset(Path("radarscenes_native.yaml"), sequence);
    EXPECT_EQ(fs::path(short_drive.radarscenes.sequence_dir).filename(), "sequence_106");
    EXPECT_EQ(ReadRadars(short_drive).size(), 100u);
    sequence.sequence = "sequence_106";
    EXPECT_EQ(LoadDatasetConfig(Path("radarscenes_native.yaml"), sequence).radarscenes.sequence_dir,
              short_drive.radarscenes.sequence_dir);
}

// --scene / --sequence choose within the data as --data DIR or data_dir: resolved it: a
// description copied elsewhere reads sequence_106 beside its sequence_dir under DIR.
TEST_F(NativeRadars, TheChoiceIsTakenFromTheDataFolder) {
    const fs::path elsewhere = dir_ / "elsewhere";
    fs::create_directories(elsewhere);
    for (const char *name : {"radarscenes_native.yaml", "nuscenes_native.yaml"})
        fs::copy_file(dir_ / name, elsewhere / name, fs::copy_options::overwrite_existing);
    DatasetChoice sequence;
    sequence.sequence = "106";
    const DatasetConfig with_data =
        ResolveDataset((elsewhere / "radarscenes_native.yaml").string(), dir_.string(), sequence);
    const fs::path expected = dir_ / "RadarScenes" / "data" / "sequence_106";
    EXPECT_TRUE(fs::equivalent(with_data.radarscenes.sequence_dir, expected))
        << with_data.radarscenes.sequence_dir;
    for (const DatasetInput &input : with_data.inputs)  // what RequireInputs checked
        if (input.key == "radarscenes.sequence_dir")
            EXPECT_EQ(input.path, with_data.radarscenes.sequence_dir);
    EXPECT_EQ(ReadRadars(with_data).size(), 100u);
    ExpectMentions(ConfigErrorOf([&] {
                       (void)ResolveDataset((elsewhere / "radarscenes_native.yaml").string(), "",
                                            sequence);
                   }),
                   {"--sequence 106", "description's folder", "--data DIR"});

    std::ofstream(elsewhere / "rs_data_dir.yaml")
        << "reader: radarscenes\ndata_dir: ..\nradarscenes: {sequence_dir: "
           "RadarScenes/data/sequence_105}\n";
    const DatasetConfig with_key =
        ResolveDataset((elsewhere / "rs_data_dir.yaml").string(), "", sequence);
    EXPECT_TRUE(fs::equivalent(with_key.radarscenes.sequence_dir, expected));

    DatasetChoice scene;
    scene.scene = "scene-0103";
    const DatasetConfig later =
        ResolveDataset((elsewhere / "nuscenes_native.yaml").string(), dir_.string(), scene);
    EXPECT_EQ(later.nuscenes.scene, "scene-0103");
    EXPECT_EQ(later.radars.size(), 1u);
}

TEST_F(NativeRadars, BadChoicesNameWhatThereIs) {
    DatasetChoice choice;
    choice.scene = "scene-061";
    ExpectMentions(
        ConfigErrorOf([&] { (void)LoadDatasetConfig(Path("nuscenes_native.yaml"), choice); }),
        {"nuscenes_native.yaml", "v1.0-mini/scene.json: no scene named 'scene-061'",
         "the scenes: scene-0061, scene-0103", "did you mean 'scene-0061'?"});
    choice = {};
    choice.sequence = "108";
    ExpectMentions(
        ConfigErrorOf([&] { (void)LoadDatasetConfig(Path("radarscenes_native.yaml"), choice); }),
        {"radarscenes_native.yaml: --sequence 108", "sequence_108 is not a folder",
         "sequence_105, sequence_106, sequence_107", "did you mean sequence_105?"});
    ExpectMentions(
        ConfigErrorOf([&] { (void)LoadDatasetConfig(Path("nuscenes_native.yaml"), choice); }),
        {"--sequence 108: chooses a RadarScenes sequence", "reader is nuscenes"});
    choice = {};
    choice.scene = "scene-0061";
    ExpectMentions(
        ConfigErrorOf([&] { (void)LoadDatasetConfig(Path("nuscenes_extracts.yaml"), choice); }),
        {"nuscenes_extracts.yaml: --scene scene-0061: chooses a nuScenes scene",
         "reader is folder"});
}

TEST_F(NativeRadars, MissingFilesAndRecordsAreNamed) {
    const auto nu = [&](const std::string &version, const std::string &channel = "") {
        return Yaml("nu_" + version + channel,
                    "reader: nuscenes\nnuscenes: {dataroot: nuscenes, version: " + version +
                        ", scene: scene-0061" + (channel.empty() ? "" : ", channel: " + channel) +
                        "}\n");
    };
    ExpectMentions(ConfigErrorOf([&] { (void)LoadDatasetConfig(nu("v9.9")); }),
                   {"nu_v9.9.yaml: the data set's radars: ",
                    "v9.9/sensor.json: cannot open the nuScenes table"});
    // Every radar: a sweep whose calibration has no record names the sample_data record.
    ExpectMentions(ConfigErrorOf([&] { (void)LoadDatasetConfig(nu("v1.0-nocal")); }),
                   {"v1.0-nocal/sample_data.json: record ", "(sweeps/RADAR_BACK_LEFT/",
                    "calibrated_sensor_token 'cs_RADAR_BACK_LEFT' has no record in "
                    "calibrated_sensor.json"});
    // That channel alone: its missing calibration is named.
    ExpectMentions(
        ConfigErrorOf([&] { (void)LoadDatasetConfig(nu("v1.0-nocal", "RADAR_BACK_LEFT")); }),
        {"v1.0-nocal/calibrated_sensor.json: no record of channel RADAR_BACK_LEFT"});
    ExpectMentions(
        ConfigErrorOf([&] { (void)LoadDatasetConfig(nu("v1.0-mini", "RADAR_FRONT_LFET")); }),
        {"sensor.json: no radar on channel 'RADAR_FRONT_LFET'",
         "did you mean 'RADAR_FRONT_LEFT'?"});
    // A channel whose sweeps have two calibrations: its mount is not known, unless given; its
    // sweeps are read.
    ExpectMentions(ConfigErrorOf([&] { (void)LoadDatasetConfig(nu("v1.0-twocal")); }),
                   {"v1.0-twocal/sample_data.json: channel RADAR_FRONT has two calibrations in "
                    "scene-0061 (cs_RADAR_FRONT, cs_front_b): read it alone (nuscenes.channel) "
                    "with its mount as extrinsics.T_base_radar"});
    const DatasetConfig mount_given = LoadDatasetConfig(
        Yaml("nu_twocal_mount",
             "reader: nuscenes\nnuscenes: {dataroot: nuscenes, version: v1.0-twocal, "
             "scene: scene-0061, channel: RADAR_FRONT}\nextrinsics: {T_base_radar: "
             "{translation_m: [3.4, 0, 0.5]}}\n"));
    const auto twocal_events = ReadRadars(mount_given);
    EXPECT_EQ(std::count_if(
                  twocal_events.begin(), twocal_events.end(),
                  [](const DatasetEvent &e) { return e.kind == DatasetEvent::Kind::kRadarScan; }),
              247);
    // A sweep's file missing: that scan is reported and skipped, naming the file.
    const DatasetConfig nopcd = LoadDatasetConfig(nu("v1.0-nopcd"));
    std::size_t bad = 0;
    for (const DatasetEvent &e : ReadRadars(nopcd)) {
        if (e.kind != DatasetEvent::Kind::kBadScan) continue;
        ++bad;
        ExpectMentions(e.problem, {"sweeps/RADAR_FRONT/absent.pcd (scan 3): cannot open"});
    }
    EXPECT_EQ(bad, 1u);
    // RadarScenes: a sequence without its radar_data.h5.
    const DatasetConfig no_h5 = LoadDatasetConfig(
        Yaml("rs_107",
             "reader: radarscenes\nradarscenes: {sequence_dir: RadarScenes/data/sequence_107}\n"));
    ASSERT_EQ(no_h5.radars.size(), 4u);
    try {
        (void)ReadRadars(no_h5);
        ADD_FAILURE() << "no error without radar_data.h5";
    } catch (const DatasetError &e) {
        ExpectMentions(e.what(), {"sequence_107/radar_data.h5"});
    }
    // A sequence folder without scenes.json (sensors.json above it).
    ExpectMentions(
        ConfigErrorOf([&] {
            (void)LoadDatasetConfig(Yaml("rs_999",
                                         "reader: radarscenes\nradarscenes: "
                                         "{sequence_dir: RadarScenes/data/sequence_999}\n"));
        }),
        {"rs_999.yaml: the data set's radars: ", "sequence_999/scenes.json: cannot open"});
    // Without sensors.json: no mounts.
    fs::rename(dir_ / "RadarScenes" / "data" / "sensors.json", dir_ / "sensors.json.away");
    const std::string message =
        ConfigErrorOf([&] { (void)LoadDatasetConfig(Path("radarscenes_native.yaml")); });
    fs::rename(dir_ / "sensors.json.away", dir_ / "RadarScenes" / "data" / "sensors.json");
    ExpectMentions(message, {"radarscenes_native.yaml: the data set's radars: ",
                             "sequence_105/sensors.json: missing"});
}

}  // namespace
}  // namespace dorado::io
