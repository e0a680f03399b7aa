// Dataset descriptions: the shipped ones load; mistakes name the file and the key.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "dorado/io/dataset_config.hpp"

namespace dorado::io {
namespace {

namespace fs = std::filesystem;

class DatasetConfigTest : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = fs::path(::testing::TempDir()) / ("dorado_cfg_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::string WriteYaml(const std::string &text) {
        const std::string path = (dir_ / "d.yaml").string();
        std::ofstream(path) << text;
        return path;
    }

    void ExpectError(const std::string &text, const std::string &needle) {
        const std::string path = WriteYaml(text);
        try {
            (void)LoadDatasetConfig(path);
            ADD_FAILURE() << "no error for:\n" << text;
        } catch (const ConfigError &e) {
            EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    }

    fs::path dir_;
};

// Every shipped description (configs/*.yaml with a `reader:`) loads: none has a key its reader does
// not read.
TEST_F(DatasetConfigTest, EveryShippedDescriptionLoads) {
    std::size_t descriptions = 0;
    for (const auto &entry : fs::directory_iterator(fs::path(DORADO_SOURCE_DIR) / "configs")) {
        if (entry.path().extension() != ".yaml") continue;
        std::ifstream in(entry.path());
        const std::string text((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
        if (text.rfind("reader:", 0) != 0 && text.find("\nreader:") == std::string::npos) continue;
        ++descriptions;
        EXPECT_NO_THROW((void)LoadDatasetConfig(entry.path().string())) << entry.path();
    }
    EXPECT_GE(descriptions, 8u);
}

// The native readers' shipped descriptions (configs/native/) point at a data set's own download,
// which is not in the repository: every key is read, and the load stops at the missing data with
// the file it looked for (the table that lists the radars), naming the root key that led there, as
// written and as resolved, and --data DIR as the data set's root.
TEST_F(DatasetConfigTest, NativeDescriptionsReadEveryKeyAndNameTheMissingData) {
    const fs::path native = fs::path(DORADO_SOURCE_DIR) / "configs" / "native";
    for (const auto &[file, missing] :
         {std::pair<std::string, std::string>{"radarscenes.yaml", "sensors.json"},
          {"nuscenes.yaml", "sensor.json"}}) {
        try {
            (void)LoadDatasetConfig((native / file).string());
            ADD_FAILURE() << file << " loaded without its data";
        } catch (const ConfigError &error) {
            const std::string what = error.what();
            EXPECT_NE(what.find(missing), std::string::npos) << what;
            const std::string key =
                file == "nuscenes.yaml" ? "nuscenes.dataroot" : "radarscenes.sequence_dir";
            for (const std::string &part :
                 {"key '" + key + "': written ../../data/", std::string("resolved "),
                  std::string("taken from the description's folder"),
                  std::string("pass --data DIR with the data set's root")})
                EXPECT_NE(what.find(part), std::string::npos) << part << "\n" << what;
        }
    }
}

// A section only another reader reads would be ignored without a word: each of its keys is named.
TEST_F(DatasetConfigTest, KeysTheReaderDoesNotReadAreErrors) {
    ExpectError("reader: rosbag\nrosbag: {path: x.bag}\nfolder: {scans_dir: s, columns: [x]}\n",
                "key 'folder.scans_dir': is not used by reader: rosbag (remove it; the keys this "
                "reader does not use: folder.scans_dir, folder.columns)");
    ExpectError(
        "reader: folder\nfolder: {scans_dir: s, timestamps_file: t, columns: [x, y, z, "
        "v]}\nrosbag: {radar_topic: /radar}\nradarscenes: {sensor_id: 3}\n",
        "key 'rosbag.radar_topic': is not used by reader: folder (remove it; the keys this "
        "reader does not use: rosbag.radar_topic, radarscenes.sensor_id)");
    ExpectError(
        "reader: folder\nfolder: {scans_dir: s, timestamps_file: t, columns: [x, y, z, "
        "v]}\nnuscenes: scene-0061\n",
        "key 'nuscenes': is not used by reader: folder");
    // An empty section sets nothing.
    EXPECT_NO_THROW((void)LoadDatasetConfig(
        WriteYaml("reader: rosbag\nrosbag: {path: x.bag}\nfolder:\nnuscenes: {scene: }\n")));
}

TEST_F(DatasetConfigTest, ShippedDescriptionsLoad) {
    for (const char *name :
         {"hugin", "view_of_delft", "coloradar", "ntu4dradlm", "ti_mmwave", "rio"}) {
        const std::string path = std::string(DORADO_SOURCE_DIR) + "/configs/" + name + ".yaml";
        EXPECT_NO_THROW((void)LoadDatasetConfig(path)) << path;
    }
    const DatasetConfig hugin =
        LoadDatasetConfig(std::string(DORADO_SOURCE_DIR) + "/configs/hugin.yaml");
    EXPECT_EQ(hugin.rosbag.radar_topic, "/hugin_raf_1/radar_data");
    // The paper's launch file: the radar sensor_to_icr_x = -0.99447 m from the ICR line, which is
    // both the Z-ICR and the Y-ICR axis of the skid-steer Husky (m = 0).
    EXPECT_NEAR(hugin.extrinsics.T_base_radar.translation().x(), 0.99447, 1e-5);
    EXPECT_DOUBLE_EQ(hugin.vehicle.half_wheelbase_m, 0.0);
    EXPECT_TRUE(fs::path(hugin.rosbag.path).is_absolute()) << "relative to the YAML file";
    const DatasetConfig vod =
        LoadDatasetConfig(std::string(DORADO_SOURCE_DIR) + "/configs/view_of_delft.yaml");
    EXPECT_EQ(vod.reader, ReaderKind::kFolder);
    EXPECT_EQ(vod.folder.columns.size(), 7u);
    EXPECT_EQ(vod.fields.doppler, "v_r");
}

TEST_F(DatasetConfigTest, RollPitchYawAreZyxEulerAnglesInDegrees) {
    const auto config =
        LoadDatasetConfig(WriteYaml("rosbag: {path: x.bag}\nextrinsics:\n  T_base_radar: "
                                    "{translation_m: [1, 2, 3], rotation_rpy_deg: [0, 0, 90]}\n"));
    const Eigen::Vector3d x_base = config.extrinsics.T_base_radar * Eigen::Vector3d(1, 0, 0);
    EXPECT_NEAR((x_base - Eigen::Vector3d(1, 3, 3)).norm(), 0.0, 1e-12)
        << "radar X points along base Y";
}

TEST_F(DatasetConfigTest, MisspelledKeySuggestsTheRightOne) {
    ExpectError("rosbag: {path: x.bag, radar_topc: /r}\n",
                "rosbag.radar_topc': unknown key (did you mean 'radar_topic'?)");
    ExpectError("rosbag: {path: x.bag}\nvehicel: {half_wheelbase_m: 1}\n",
                "'vehicel': unknown key (did you mean 'vehicle'?)");
}

TEST_F(DatasetConfigTest, OutOfRangeAndWrongTypesNameTheKey) {
    ExpectError("rosbag: {path: x.bag}\nvehicle: {half_wheelbase_m: -1}\n",
                "vehicle.half_wheelbase_m': must be a number >= 0");
    ExpectError("rosbag: {path: x.bag}\nvehicle: {half_wheelbase_m: wide}\n",
                "vehicle.half_wheelbase_m': has the wrong type (line 2)");
    ExpectError("rosbag: {path: x.bag}\nvehicle: {model_noise: {sigma_vertical_mps: -0.1}}\n",
                "vehicle.model_noise.sigma_vertical_mps': must be a number >= 0");
    ExpectError("rosbag: {path: x.bag}\nvehicle: {model_noise: {sigma_roll_rate: 0.1}}\n",
                "vehicle.model_noise.sigma_roll_rate': unknown key");
    ExpectError(
        "rosbag: {path: x.bag}\nvehicle: {model_noise: {angular_rate_prior_sigma_radps: [1, 0, "
        "1]}}\n",
        "vehicle.model_noise.angular_rate_prior_sigma_radps': must be 3 numbers > 0");
    ExpectError("rosbag: {path: x.bag}\nfields: {doppler_sign: 2}\n",
                "fields.doppler_sign': must be 1 or -1");
    ExpectError("reader: lidar\n", "'reader': must be rosbag, folder, radarscenes or nuscenes");
    ExpectError("reader: rosbag\n", "'rosbag.path': is required");
    ExpectError("reader: folder\nfolder: {scans_dir: s, timestamps_file: t}\n",
                "'folder.columns': is required");
    ExpectError("rosbag: {path: x.bag}\nextrinsics: {T_base_radar: {translation_m: [1, 2]}}\n",
                "extrinsics.T_base_radar.translation_m': must have 3 values");
    ExpectError("rosbag: {path: x.bag\n", "not valid YAML");
}

TEST_F(DatasetConfigTest, VelocityPriorAndSeveralRadars) {
    // nuScenes: 5 radars with mounts.txt's mounts; the ground vehicle's velocity prior on.
    const DatasetConfig ns =
        LoadDatasetConfig(std::string(DORADO_SOURCE_DIR) + "/configs/nuscenes.yaml");
    ASSERT_EQ(ns.radars.size(), 5u);
    EXPECT_EQ(ns.radars[1].name, "left");
    EXPECT_EQ(ns.radars[1].T_base_radar.translation(), Eigen::Vector3d(2.422, 0.8, 0.78));
    // left looks left: its x axis is the base's y (yaw ~88.4 deg).
    EXPECT_NEAR(ns.radars[1].T_base_radar.linear()(1, 0), 1.0, 1e-3);
    EXPECT_TRUE(fs::path(ns.radars[1].scans_dir).is_absolute()) << "relative to the YAML file";
    const DatasetConfig left = ForRadar(ns, 1);
    EXPECT_EQ(left.folder.scans_dir, ns.radars[1].scans_dir);
    EXPECT_EQ(left.folder.timestamps_file, ns.radars[1].timestamps_file);
    EXPECT_EQ(left.folder.columns, ns.folder.columns);
    EXPECT_TRUE(left.extrinsics.T_base_radar.isApprox(ns.radars[1].T_base_radar));
    EXPECT_TRUE(left.radars.empty());
    EXPECT_TRUE(ns.vehicle.velocity_prior.enabled);
    EXPECT_FALSE(DatasetConfig{}.vehicle.velocity_prior.enabled) << "off by default";
    const std::string bag = "rosbag: {path: x.bag}\n";
    ExpectError(bag + "vehicle: {model: unconstrained, velocity_prior: {enabled: true}}\n",
                "'vehicle.velocity_prior.enabled'");
    ExpectError(bag + "vehicle: {velocity_prior: {sigma_vertical_mps: 0}}\n",
                "'vehicle.velocity_prior.sigma_vertical_mps': must be a number > 0");
    ExpectError(bag +
                    "radars: [{name: a, scans_dir: s, timestamps_file: t, "
                    "T_base_radar: {translation_m: [1, 0, 0]}}]\n",
                "'radars': needs reader: folder");
    const std::string folder =
        "reader: folder\nfolder: {scans_dir: s, timestamps_file: t, columns: [x, y, z, v]}\n";
    ExpectError(folder + "radars: [{name: a, scans_dir: s, timestamps_file: t}]\n",
                "'radars[0].T_base_radar': is required");
    ExpectError(folder +
                    "radars: [{name: a, scans_dir: s, timestamps_file: t, "
                    "T_base_radar: {translation_m: [1, 0, 0]}, topic: x}]\n",
                "topic");
}

TEST_F(DatasetConfigTest, YamlRoundTrip) {
    DatasetConfig config;
    config.name = "sim";
    config.rosbag.path = (dir_ / "data.bag").string();
    config.rosbag.imu_topic = "/imu/data";
    config.fields.doppler_sign = -1;
    config.extrinsics.T_base_radar.linear() =
        Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    config.extrinsics.T_base_radar.translation() << 0.7, 0.01, 0.45;
    config.vehicle.half_wheelbase_m = 0.3;
    config.vehicle.model_noise = {0.25, 0.001, 0.03, 0.07, 0.11, {0.3, 0.2, 2.5}};
    config.ground_truth.path = (dir_ / "gt.tum").string();
    config.radar = {0.08, 0.5, 2.0, 11.5};
    const DatasetConfig back = LoadDatasetConfig(WriteYaml(DatasetConfigToYaml(config)));
    EXPECT_EQ(back.name, "sim");
    EXPECT_EQ(back.rosbag.path, config.rosbag.path);
    EXPECT_EQ(back.rosbag.imu_topic, "/imu/data");
    EXPECT_EQ(back.fields.doppler_sign, -1);
    EXPECT_LT(
        (back.extrinsics.T_base_radar.matrix() - config.extrinsics.T_base_radar.matrix()).norm(),
        1e-14);
    EXPECT_EQ(back.vehicle.half_wheelbase_m, 0.3);
    EXPECT_EQ(back.vehicle.model_noise.sigma_icr_x_m, 0.25);
    EXPECT_EQ(back.vehicle.model_noise.rear_slip_rad_per_mps2, 0.001);
    EXPECT_EQ(back.vehicle.model_noise.sigma_lateral_mps, 0.03);
    EXPECT_EQ(back.vehicle.model_noise.sigma_vertical_mps, 0.07);
    EXPECT_EQ(back.vehicle.model_noise.sigma_roll_rate_radps, 0.11);
    EXPECT_EQ(back.vehicle.model_noise.angular_rate_prior_sigma_radps,
              Eigen::Vector3d(0.3, 0.2, 2.5));
    EXPECT_EQ(back.ground_truth.path, config.ground_truth.path);
    EXPECT_EQ(back.radar.range_sigma_m, 0.08);
    EXPECT_EQ(back.radar.azimuth_sigma_deg, 0.5);
    EXPECT_EQ(back.radar.elevation_sigma_deg, 2.0);
    EXPECT_EQ(back.radar.doppler_unambiguous_mps, 11.5);
}

TEST_F(DatasetConfigTest, RadarSectionNamesBadKeys) {
    ExpectError("rosbag: {path: x.bag}\nradar: {elevation_sigma_deg: -2}\n",
                "radar.elevation_sigma_deg': must be a number in [0, 20");
    ExpectError("rosbag: {path: x.bag}\nradar: {doppler_unambiguous: 11}\n",
                "radar.doppler_unambiguous': unknown key");
    const DatasetConfig none = LoadDatasetConfig(WriteYaml("rosbag: {path: x.bag}\n"));
    EXPECT_FALSE(none.radar.has_direction_noise());
    EXPECT_EQ(none.radar.doppler_unambiguous_mps, 0.0);
}

TEST_F(DatasetConfigTest, ResolveDatasetAcceptsBagsYamlAndFolders) {
    EXPECT_THROW((void)ResolveDataset((dir_ / "nothing.bag").string()), ConfigError);
    std::ofstream((dir_ / "x.bag").string()) << "not really";
    const DatasetConfig bag = ResolveDataset((dir_ / "x.bag").string());
    EXPECT_EQ(bag.rosbag.radar_topic, "/hugin_raf_1/radar_data");
    WriteYaml("rosbag: {path: x.bag}\n");
    fs::copy_file(dir_ / "d.yaml", dir_ / "dataset.yaml");
    EXPECT_EQ(ResolveDataset(dir_.string()).rosbag.path, (dir_ / "x.bag").string());
    EXPECT_THROW((void)ResolveDataset((dir_ / "d.txt").string()), ConfigError);
}

}  // namespace
}  // namespace dorado::io

namespace dorado::io {
namespace {

TEST_F(DatasetConfigTest, VehicleModelAndRadarTrigger) {
    const DatasetConfig c = LoadDatasetConfig(WriteYaml(
        "rosbag: {path: x.bag, radar_trigger_topic: /trigger, radar_trigger_offset_s: -0.09}\n"
        "vehicle: {model: unconstrained}\n"));
    EXPECT_EQ(c.vehicle.model, VehicleModel::kUnconstrained);
    EXPECT_EQ(c.rosbag.radar_trigger_topic, "/trigger");
    EXPECT_DOUBLE_EQ(c.rosbag.radar_trigger_offset_s, -0.09);
    const DatasetConfig back = LoadDatasetConfig(WriteYaml(DatasetConfigToYaml(c)));
    EXPECT_EQ(back.vehicle.model, VehicleModel::kUnconstrained);
    EXPECT_EQ(back.rosbag.radar_trigger_topic, "/trigger");
    EXPECT_EQ(LoadDatasetConfig(WriteYaml("rosbag: {path: x.bag}\nvehicle: {model: skid_steer}\n"))
                  .vehicle.half_wheelbase_m,
              0.0);
    ExpectError("rosbag: {path: x.bag}\nvehicle: {model: drone}\n", "vehicle.model");
    ExpectError("rosbag: {path: x.bag}\nvehicle: {model: skid_steer, half_wheelbase_m: 0.3}\n",
                "half_wheelbase_m");
    ExpectError("rosbag: {path: x.bag, radar_trigger_offset_s: 2}\n", "radar_trigger_offset_s");
}

}  // namespace
}  // namespace dorado::io
