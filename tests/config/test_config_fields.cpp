// One truth per default: the shipped configs/odometry.yaml and configs/mapper.yaml
// load to exactly the structs' built-in defaults, write every key the reader accepts,
// docs/config_keys.md is what the field lists generate, and every key reads back a value that
// differs from its default (so no key is read into the wrong member or dropped).
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "config_keys.hpp"  // apps/: it gathers every layer's field lists
#include "dorado/config/map_config.hpp"
#include "dorado/config/odometry_config.hpp"

namespace dorado::config {
namespace {

const std::string kOdometryYaml = DORADO_SOURCE_DIR "/configs/odometry.yaml";
const std::string kMapperYaml = DORADO_SOURCE_DIR "/configs/mapper.yaml";

/// Every field equal, or the first key that is not (with both values).
void ExpectSameFields(const std::vector<FieldRow> &actual, const std::vector<FieldRow> &expected,
                      const std::string &what) {
    ASSERT_EQ(actual.size(), expected.size());
    for (std::size_t i = 0; i < actual.size(); ++i) {
        ASSERT_EQ(actual[i].key, expected[i].key);
        EXPECT_EQ(actual[i].value, expected[i].value)
            << what << ": key '" << actual[i].key << "' is " << actual[i].value
            << ", the struct's default is " << expected[i].value;
    }
}

/// Whether the file writes the dotted key (each part a key of the mapping above it).
bool Writes(const YAML::Node &node, const std::string &dotted) {
    const auto dot = dotted.find('.');
    const std::string part = dotted.substr(0, dot);
    if (!node.IsMap() || !node[part]) return false;
    return dot == std::string::npos || Writes(node[part], dotted.substr(dot + 1));
}

TEST(ConfigFields, ShippedOdometryYamlIsTheBuiltInDefaults) {
    ExpectSameFields(ListFields(LoadOdometryConfig(kOdometryYaml)), OdometryConfigFields(),
                     kOdometryYaml);
}

TEST(ConfigFields, ShippedMapperYamlIsTheBuiltInDefaults) {
    ExpectSameFields(ListFields(LoadMapConfig(kMapperYaml)), MapConfigFields(), kMapperYaml);
}

TEST(ConfigFields, ShippedYamlsWriteEveryKeyTheReaderAccepts) {
    const YAML::Node odometry = YAML::LoadFile(kOdometryYaml);
    for (const auto &row : OdometryConfigFields())
        EXPECT_TRUE(Writes(odometry, row.key)) << kOdometryYaml << " lacks " << row.key;
    const YAML::Node mapper = YAML::LoadFile(kMapperYaml);
    for (const auto &row : MapConfigFields())
        EXPECT_TRUE(Writes(mapper, row.key)) << kMapperYaml << " lacks " << row.key;
}

TEST(ConfigFields, DocsKeyTablesAreTheFieldLists) {
    std::ifstream file(DORADO_SOURCE_DIR "/docs/config_keys.md");
    std::stringstream text;
    text << file.rdbuf();
    EXPECT_EQ(text.str(), apps::ConfigKeysMarkdown())
        << "docs/config_keys.md is stale: run `dorado config keys > docs/config_keys.md`";
}

/// Sets every field to a valid value other than its default.
struct Perturb {
    void operator()(const char *, double &x, const char *) {
        x = std::isinf(x) ? -100.0 : x == 0.0 ? 0.25 : 0.75 * x;
    }
    void operator()(const char *, int &x, const char *) { x += 1; }
    void operator()(const char *, std::uint64_t &x, const char *) { x += 1; }
    void operator()(const char *, bool &x, const char *) { x = !x; }
    void operator()(const char *key, Eigen::Vector3d &x, const char *doc) {
        for (int i = 0; i < 3; ++i) (*this)(key, x[i], doc);
    }
    template <typename E>
    void operator()(const char *, E &x, const Choices<E> &names, const char *) {
        for (std::size_t i = 0; i < names.size(); ++i) {
            if (names[i].second == x) {
                x = names[(i + 1) % names.size()].second;
                return;
            }
        }
    }
};

template <typename Config, typename Load, typename Write>
void ExpectEveryKeyReadsBack(Load load, Write write, const std::string &name) {
    Config changed;
    VisitFields(changed, Perturb{});
    const std::string path = ::testing::TempDir() + name;
    std::ofstream(path) << write(changed);
    const auto defaults = ListFields(Config{});
    const auto expected = ListFields(changed);
    for (std::size_t i = 0; i < expected.size(); ++i)
        ASSERT_NE(expected[i].value, defaults[i].value) << expected[i].key;
    ExpectSameFields(ListFields(load(path)), expected, path);
}

TEST(ConfigFields, EveryOdometryKeyReadsBackAValueOtherThanItsDefault) {
    ExpectEveryKeyReadsBack<odometry::DopplerOdometryConfig>(LoadOdometryConfig, OdometryConfigYaml,
                                                             "odometry_changed.yaml");
}

TEST(ConfigFields, EveryMapperKeyReadsBackAValueOtherThanItsDefault) {
    ExpectEveryKeyReadsBack<MapCommandConfig>(LoadMapConfig, MapConfigYaml, "mapper_changed.yaml");
}

TEST(ConfigFields, PrintedDefaultsReadBackAsTheDefaults) {
    const std::string path = ::testing::TempDir() + "mapper_printed.yaml";
    std::ofstream(path) << MapConfigYaml(MapCommandConfig{});
    ExpectSameFields(ListFields(LoadMapConfig(path)), MapConfigFields(), path);
}

}  // namespace
}  // namespace dorado::config
