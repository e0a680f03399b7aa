// The dataset description's field list (io/dataset_fields.hpp) is the whole struct: every member of
// DatasetConfig holds a key of the list, and every key, set to a value other than its default,
// reads back through DatasetConfigToYaml + LoadDatasetConfig under each reader.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "dorado/io/dataset_config.hpp"
#include "dorado/io/dataset_fields.hpp"
#include "dorado/io/field_yaml.hpp"
#include "dorado/testing/field_coverage.hpp"
#include "dorado/testing/field_perturb.hpp"

namespace dorado::io {
namespace {

/// The rows as "key: value" lines, to compare.
std::string Text(const std::vector<FieldRow> &rows) {
    std::string text;
    for (const auto &row : rows) text += row.key + ": " + row.value + "\n";
    return text;
}

TEST(DatasetFields, EveryMemberIsAField) {
    DatasetConfig config;
    // config_path, path_base, path_base_dir, inputs: where it came from and how its paths were
    // resolved; radars: a list, each radar RadarStream's list; mount_source: derived (where the
    // mount came from), not a key.
    EXPECT_EQ(testing::MembersWithoutField(
                  config, {&config.config_path, &config.path_base, &config.path_base_dir,
                           &config.inputs, &config.radars, &config.mount_source}),
              std::vector<std::string>{});
    // The data sets' own readers fill these from their files: no key.
    RadarStream radar;
    EXPECT_EQ(testing::MembersWithoutField(radar,
                                           {&radar.radarscenes_sensor_id, &radar.nuscenes_channel}),
              std::vector<std::string>{});
}

// The perturbed description for @p reader, mended where the reader's checks would refuse it.
DatasetConfig Perturbed(ReaderKind reader) {
    DatasetConfig config;
    VisitFields(config, testing::Perturb{});
    config.reader = reader;
    config.folder.extension = ".pcd";
    config.fields.doppler_sign = -1.0;
    config.vehicle.model = VehicleModel::kSkidSteer;
    config.vehicle.half_wheelbase_m = 0.0;                       // skid_steer's
    if (reader == ReaderKind::kRosbag) config.imu.path.clear();  // the bag's IMU topic instead
    for (int k = 0; k < 2; ++k) {
        RadarStream radar;
        VisitFields(radar, testing::Perturb{"/radar" + std::to_string(k)});
        if (reader == ReaderKind::kFolder) config.radars.push_back(radar);
    }
    return config;
}

TEST(DatasetFields, EveryKeyReadsBackUnderEachReader) {
    const auto defaults = ListFields(DatasetConfig{});
    std::vector<std::string> read_back;  // keys that read back a value other than the default
    for (const auto &[name, reader] : ReaderKindChoices()) {
        const DatasetConfig changed = Perturbed(reader);
        const std::string path = ::testing::TempDir() + "dataset_" + name + ".yaml";
        std::ofstream(path) << DatasetConfigToYaml(changed);
        const DatasetConfig back = LoadDatasetConfig(path);
        const auto expected = ListFields(changed);
        const auto actual = ListFields(back);
        ASSERT_EQ(actual.size(), expected.size());
        for (std::size_t i = 0; i < actual.size(); ++i) {
            const std::string &key = actual[i].key;
            if (actual[i].value == expected[i].value && actual[i].value != defaults[i].value)
                read_back.push_back(key);
        }
        ASSERT_EQ(back.radars.size(), changed.radars.size()) << name;
        for (std::size_t k = 0; k < back.radars.size(); ++k) {
            EXPECT_EQ(Text(ListFields(back.radars[k])), Text(ListFields(changed.radars[k])));
            EXPECT_NE(Text(ListFields(back.radars[k])), Text(ListFields(RadarStream{})));
        }
    }
    for (const auto &row : defaults) {
        if (row.key == "imu.format") continue;  // one choice only: no other value
        EXPECT_TRUE(std::count(read_back.begin(), read_back.end(), row.key))
            << "key '" << row.key << "' does not read back a value other than its default";
    }
}

TEST(DatasetFields, PathsAreNormalisedRelativeToTheFile) {
    const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "paths_cfg";
    std::filesystem::create_directories(dir / "sub");
    const std::string path = (dir / "sub" / "d.yaml").string();
    std::ofstream(path) << "reader: radarscenes\nradarscenes: {sequence_dir: ../data/./seq/, "
                           "sensor_id: 1}\nextrinsics: {T_base_radar: {}}\n";
    const DatasetConfig config = LoadDatasetConfig(path);
    EXPECT_EQ(config.radarscenes.sequence_dir, (dir / "data" / "seq").string());
    EXPECT_EQ(std::filesystem::path(config.radarscenes.sequence_dir).parent_path(), dir / "data");
}

}  // namespace
}  // namespace dorado::io
