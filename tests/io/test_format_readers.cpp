// The data sets' own formats: RadarScenes' radar_data.h5 + scenes.json + sensors.json and nuScenes'
// PCD sweeps + JSON tables, written in those schemas by make_format_fixtures.py from the shared
// real folders' first scans (synthetic ones when ../shared/data/real is absent). The truth is what
// the generator put in (its expected/ files) and, when present, the shared folders themselves.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "dorado/io/dataset.hpp"
#include "dorado/testing/dataset_events.hpp"

namespace dorado::io {
namespace {

namespace fs = std::filesystem;

constexpr int kScans = 20;
constexpr int64_t kOffsetNs = 1533151603000000LL * 1000;  // make_format_fixtures.TIME_OFFSET_US

// ../shared/data/real next to the checkout, or DORADO_SHARED_REAL (a checkout elsewhere).
const fs::path kShared = std::getenv("DORADO_SHARED_REAL")
                             ? fs::path(std::getenv("DORADO_SHARED_REAL"))
                             : fs::path(DORADO_SOURCE_DIR) / ".." / "shared" / "data" / "real";

struct Rows {
    std::vector<std::vector<float>> scans;  // 6 floats a point: x y z rcs v_r label
    std::vector<double> times_s;
};

// A folder of scans/NNNNN.bin (float32 rows of 6) and times.txt, the first `count` scans.
Rows ReadFolder(const fs::path &dir, int count) {
    Rows rows;
    std::ifstream times(dir / "times.txt");
    for (double t; rows.times_s.size() < static_cast<std::size_t>(count) && times >> t;)
        rows.times_s.push_back(t);
    for (int k = 0; k < count; ++k) {
        char name[16];
        std::snprintf(name, sizeof(name), "%05d.bin", k);
        std::ifstream in(dir / "scans" / name, std::ios::binary);
        std::vector<float> values;
        for (float v; in.read(reinterpret_cast<char *>(&v), sizeof(v));) values.push_back(v);
        rows.scans.push_back(values);
    }
    return rows;
}

class FormatReaders : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        dir_ = fs::path(::testing::TempDir()) / ("dorado_formats_" + std::to_string(::getpid()));
        const std::string cmd = std::string(DORADO_SYSTEM_PYTHON) + " " + DORADO_SOURCE_DIR +
                                "/tests/io/make_format_fixtures.py " + kShared.string() + " " +
                                dir_.string() + " " + std::to_string(kScans);
        ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    }
    static void TearDownTestSuite() { fs::remove_all(dir_); }

    static std::string Yaml(const std::string &name, const std::string &body) {
        const fs::path path = dir_ / (name + ".yaml");
        std::ofstream(path) << "name: " << name << "\n" << body;
        return path.string();
    }
    static DatasetConfig RadarScenes(const std::string &sequence = "sequence_105", int id = 3) {
        return LoadDatasetConfig(Yaml("rs_" + sequence + std::to_string(id),
                                      "reader: radarscenes\nradarscenes:\n  sequence_dir: " +
                                          (dir_ / "radarscenes" / sequence).string() +
                                          "\n  sensor_id: " + std::to_string(id) + "\n"));
    }
    static std::string NuScenesYaml(const std::string &channel, const std::string &version) {
        return Yaml("nu_" + channel + version,
                    "reader: nuscenes\nnuscenes:\n  dataroot: " + (dir_ / "nuscenes").string() +
                        "\n  version: " + version + "\n  scene: scene-0061\n  channel: " + channel +
                        "\n");
    }
    static DatasetConfig NuScenes(const std::string &channel = "RADAR_FRONT") {
        return LoadDatasetConfig(NuScenesYaml(channel, "v1.0-mini"));
    }

    // The reader's scans equal `truth`'s: times to the microsecond, points to float precision.
    // `doppler_tol` covers nuScenes' Doppler formed from float32 vx, vy.
    static void ExpectSameScans(const std::vector<DatasetEvent> &events, const Rows &truth,
                                double doppler_tol) {
        ASSERT_EQ(events.size(), truth.scans.size());
        for (std::size_t k = 0; k < events.size(); ++k) {
            const DatasetEvent &e = events[k];
            ASSERT_EQ(e.kind, DatasetEvent::Kind::kRadarScan) << e.problem;
            EXPECT_EQ(e.scan_index, k);
            EXPECT_NEAR(static_cast<double>(e.stamp_ns - kOffsetNs), truth.times_s[k] * 1e9, 500)
                << "scan " << k;
            const auto &rows = truth.scans[k];
            ASSERT_EQ(static_cast<std::size_t>(e.scan.size()) * 6, rows.size()) << "scan " << k;
            EXPECT_TRUE(e.scan.has_power);
            for (Eigen::Index i = 0; i < e.scan.size(); ++i) {
                const float *r = &rows[static_cast<std::size_t>(6 * i)];
                const double range = std::hypot(r[0], r[1]);
                EXPECT_NEAR(e.scan.xyz_radar(0, i), r[0], 1e-6 * range + 1e-6) << k << "/" << i;
                EXPECT_NEAR(e.scan.xyz_radar(1, i), r[1], 1e-6 * range + 1e-6) << k << "/" << i;
                EXPECT_EQ(e.scan.xyz_radar(2, i), 0.0);
                EXPECT_EQ(e.scan.power_db[i], r[3]);
                EXPECT_NEAR(e.scan.doppler_mps[i], r[4], doppler_tol) << k << "/" << i;
            }
        }
    }

    static fs::path dir_;
};

fs::path FormatReaders::dir_;

TEST_F(FormatReaders, RadarScenesScansTimesAndMountAreThoseWrittenIn) {
    const DatasetConfig config = RadarScenes();
    // sensors.json (next to the sequence folder): radar_3 at x 3.86, y 0.70, yaw 0.436.
    EXPECT_NEAR(config.extrinsics.T_base_radar.translation().x(), 3.86, 1e-12);
    EXPECT_NEAR(config.extrinsics.T_base_radar.translation().y(), 0.70, 1e-12);
    const Eigen::Matrix3d R = config.extrinsics.T_base_radar.linear();
    EXPECT_NEAR(std::atan2(R(1, 0), R(0, 0)), 0.436, 1e-12);
    // The scenes of sensor 1 in between are not read.
    ExpectSameScans(testing::ReadAllEvents(config),
                    ReadFolder(dir_ / "radarscenes" / "expected", kScans), 0.0);
}

TEST_F(FormatReaders, RadarScenesOdometryIsTheReference) {
    const auto trajectory = LoadGroundTruth(RadarScenes());
    ASSERT_TRUE(trajectory.has_value());
    std::ifstream expected(dir_ / "radarscenes" / "expected" / "odometry.txt");
    std::size_t i = 0;
    for (double t_us, x, y, yaw; expected >> t_us >> x >> y >> yaw; ++i) {
        ASSERT_LT(i, trajectory->size());
        const StampedPose &p = (*trajectory)[i];
        EXPECT_EQ(p.stamp_ns - kOffsetNs, static_cast<int64_t>(std::llround(t_us)) * 1000);
        EXPECT_NEAR(p.T_world_body.translation().x(), x, 1e-3);
        EXPECT_NEAR(p.T_world_body.translation().y(), y, 1e-3);
        const Eigen::Matrix3d R = p.T_world_body.linear();
        EXPECT_NEAR(std::atan2(R(1, 0), R(0, 0)), yaw, 1e-6);
    }
    EXPECT_EQ(i, trajectory->size());
    EXPECT_EQ(i, static_cast<std::size_t>(kScans));
}

TEST_F(FormatReaders, RadarScenesMalformedFilesNameTheFileAndTheField) {
    const auto expect = [](const std::string &what, const std::string &part) {
        EXPECT_NE(what.find(part), std::string::npos) << what;
    };
    const std::string h5 = "radar_data.h5";
    expect(testing::ReadAllEventsError(RadarScenes("missing_dataset")),
           "missing_dataset/" + h5 + ": no dataset 'radar_data'");
    expect(testing::ReadAllEventsError(RadarScenes("missing_field")),
           "missing_field/" + h5 + ": radar_data.vr: no such field (fields: timestamp, sensor_id");
    expect(testing::ReadAllEventsError(RadarScenes("wrong_dtype")),
           "wrong_dtype/" + h5 + ": radar_data.vr: an integer field, expected a float");
    expect(testing::ReadAllEventsError(RadarScenes("truncated")),
           "truncated/" + h5 + ": cannot open as an HDF5 file");
    expect(testing::ReadAllEventsError(RadarScenes("sequence_105", 2)),
           "scenes.json: no scene of sensor_id 2 (the sequence has sensors 1, 3)");
}

// "sequence_105/" is the folder "sequence_105": sensors.json is looked for in it and next to it
// (its parent_path() once was the folder itself, and the mount was "missing").
TEST_F(FormatReaders, RadarScenesSequenceDirWithATrailingSlashIsTheSameFolder) {
    const DatasetConfig plain = RadarScenes();
    const std::string absolute = (dir_ / "radarscenes" / "sequence_105").string() + "/";
    for (const std::string &dir :
         {absolute, absolute + "/", std::string("radarscenes/./sequence_105/")}) {
        SCOPED_TRACE(dir);
        DatasetConfig config;
        ASSERT_NO_THROW(config = LoadDatasetConfig(
                            Yaml("rs_slash", "reader: radarscenes\nradarscenes:\n  sequence_dir: " +
                                                 dir + "\n  sensor_id: 3\n")));
        EXPECT_EQ(config.radarscenes.sequence_dir, plain.radarscenes.sequence_dir);
        EXPECT_TRUE(config.extrinsics.T_base_radar.isApprox(plain.extrinsics.T_base_radar, 1e-12));
        ExpectSameScans(testing::ReadAllEvents(config),
                        ReadFolder(dir_ / "radarscenes" / "expected", kScans), 0.0);
    }
    DatasetConfig in_code = plain;  // not through the YAML loader
    in_code.radarscenes.sequence_dir += "/";
    ExpectSameScans(testing::ReadAllEvents(in_code),
                    ReadFolder(dir_ / "radarscenes" / "expected", kScans), 0.0);
    EXPECT_TRUE(LoadGroundTruth(in_code).has_value());
}

// The data sets' own readers decode their own fields: a field map, or another reader's section, is
// an error naming every such key (it was ignored without a word).
TEST_F(FormatReaders, KeysTheFormatReadersDoNotReadAreErrors) {
    const auto error_of = [](const std::string &path) -> std::string {
        try {
            (void)LoadDatasetConfig(path);
        } catch (const ConfigError &e) {
            return e.what();
        }
        return "(no error)";
    };
    const std::string rs = "reader: radarscenes\nradarscenes:\n  sequence_dir: " +
                           (dir_ / "radarscenes" / "sequence_105").string() + "\n  sensor_id: 3\n";
    const std::string sign = Yaml("rs_sign", rs + "fields:\n  doppler_sign: -1\n");
    EXPECT_EQ(error_of(sign), sign +
                                  ": key 'fields.doppler_sign': is not used by reader: radarscenes "
                                  "(remove it; the keys this reader does not use: "
                                  "fields.doppler_sign)");
    const std::string leftover =
        Yaml("rs_leftover", rs + "folder:\n  scans_dir: scans\n  extension: .bin\n"
                                 "nuscenes: {channel: RADAR_FRONT}\nfields: {power: rcs}\n");
    EXPECT_EQ(error_of(leftover),
              leftover +
                  ": key 'folder.scans_dir': is not used by reader: radarscenes (remove it; the "
                  "keys this reader does not use: folder.scans_dir, folder.extension, "
                  "nuscenes.channel, fields.power)");
    const std::string nu_bag =
        Yaml("nu_bag", "reader: nuscenes\nnuscenes: {dataroot: " + (dir_ / "nuscenes").string() +
                           ", version: v1.0-mini, scene: scene-0061, channel: RADAR_FRONT}\n"
                           "rosbag: {radar_topic: /radar}\nradarscenes: {sensor_id: 3}\n");
    EXPECT_EQ(error_of(nu_bag),
              nu_bag +
                  ": key 'rosbag.radar_topic': is not used by reader: nuscenes (remove it; the "
                  "keys this reader does not use: rosbag.radar_topic, radarscenes.sensor_id)");
}

TEST_F(FormatReaders, NuScenesSweepsTimesAndMountAreThoseWrittenIn) {
    const DatasetConfig config = NuScenes();
    // calibrated_sensor of RADAR_FRONT (mounts.txt's front row).
    EXPECT_NEAR(config.extrinsics.T_base_radar.translation().x(), 3.412, 1e-9);
    EXPECT_NEAR(config.extrinsics.T_base_radar.translation().z(), 0.5, 1e-9);
    const Eigen::Quaterniond q(config.extrinsics.T_base_radar.linear());
    EXPECT_NEAR(std::abs(q.z()), 0.001745328366, 1e-9);
    // The other scene's sweep and the other channels are not read; the Doppler is the line-of-sight
    // part of vx, vy (the generator adds a tangential part up to 3 m/s).
    ExpectSameScans(testing::ReadAllEvents(config),
                    ReadFolder(dir_ / "nuscenes" / "expected", kScans), 2e-5);
}

TEST_F(FormatReaders, NuScenesEgoPosesAreTheReference) {
    const auto trajectory = LoadGroundTruth(NuScenes());
    ASSERT_TRUE(trajectory.has_value());
    std::ifstream expected(dir_ / "nuscenes" / "expected" / "ego_poses.txt");
    std::size_t i = 0;
    for (double t, x, y, z, qw, qx, qy, qz; expected >> t >> x >> y >> z >> qw >> qx >> qy >> qz;
         ++i) {
        ASSERT_LT(i, trajectory->size());
        const StampedPose &p = (*trajectory)[i];
        EXPECT_NEAR(static_cast<double>(p.stamp_ns - kOffsetNs), t * 1e9, 500);
        EXPECT_NEAR((p.T_world_body.translation() - Eigen::Vector3d(x, y, z)).norm(), 0.0, 1e-6);
        const Eigen::Quaterniond q(p.T_world_body.linear());
        EXPECT_NEAR(std::abs(q.dot(Eigen::Quaterniond(qw, qx, qy, qz).normalized())), 1.0, 1e-9);
    }
    EXPECT_EQ(i, trajectory->size());
    EXPECT_GE(i, static_cast<std::size_t>(kScans));
}

TEST_F(FormatReaders, NuScenesMalformedSweepsAreSkipsNamingTheFileAndTheField) {
    const auto events = testing::ReadAllEvents(NuScenes("RADAR_BACK_LEFT"));
    ASSERT_EQ(events.size(), 5u);
    EXPECT_EQ(events[0].kind, DatasetEvent::Kind::kRadarScan) << events[0].problem;
    const std::pair<const char *, const char *> bad[] = {
        {"truncated.pcd (scan 1): truncated: ", "points of 43 bytes need"},
        {"vx_int16.pcd (scan 2): field 'vx' is I2 x1, expected one float32", ""},
        {"no_vy.pcd (scan 3): missing field 'vy'", ""},
        {"huge_points.pcd (scan 4): truncated: 428994048225803526 points of 43 bytes", ""}};
    for (std::size_t k = 1; k < 5; ++k) {
        EXPECT_EQ(events[k].kind, DatasetEvent::Kind::kBadScan);
        EXPECT_NE(events[k].problem.find(bad[k - 1].first), std::string::npos) << events[k].problem;
        EXPECT_NE(events[k].problem.find(bad[k - 1].second), std::string::npos)
            << events[k].problem;
    }
    try {
        (void)LoadDatasetConfig(NuScenesYaml("RADAR_FRONT", "v9.9"));
        FAIL() << "a version without tables";
    } catch (const ConfigError &e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("nu_RADAR_FRONTv9.9.yaml: the radar's mount: "), std::string::npos)
            << what;
        EXPECT_NE(what.find("nuscenes/v9.9/sensor.json: cannot open the nuScenes table"),
                  std::string::npos)
            << what;
    }
}

TEST_F(FormatReaders, DescriptionsRoundTripThroughYaml) {
    for (const DatasetConfig &config : {RadarScenes(), NuScenes()}) {
        const std::string path = Yaml("round_trip", DatasetConfigToYaml(config));
        const DatasetConfig back = LoadDatasetConfig(path);
        EXPECT_EQ(back.reader, config.reader);
        EXPECT_EQ(back.radarscenes.sequence_dir, config.radarscenes.sequence_dir);
        EXPECT_EQ(back.radarscenes.sensor_id, config.radarscenes.sensor_id);
        EXPECT_EQ(back.nuscenes.channel, config.nuscenes.channel);
        EXPECT_EQ(back.nuscenes.scene, config.nuscenes.scene);
        EXPECT_TRUE(back.extrinsics.T_base_radar.isApprox(config.extrinsics.T_base_radar, 1e-12));
    }
}

// The shared folders (converted from the same data sets): the readers give their scans and times.
TEST_F(FormatReaders, SameScansAndTimesAsTheSharedFolders) {
    if (!fs::exists(kShared / "radarscenes_105_radar3" / "times.txt") ||
        !fs::exists(kShared / "nuscenes_scene-0061" / "radar_front" / "times.txt"))
        GTEST_SKIP() << "the shared real sets are absent (" << kShared.string()
                     << ", or set DORADO_SHARED_REAL): the fixtures were synthetic";
    ExpectSameScans(testing::ReadAllEvents(RadarScenes()),
                    ReadFolder(kShared / "radarscenes_105_radar3", kScans), 0.0);
    ExpectSameScans(testing::ReadAllEvents(NuScenes()),
                    ReadFolder(kShared / "nuscenes_scene-0061" / "radar_front", kScans), 2e-5);
}

}  // namespace
}  // namespace dorado::io
