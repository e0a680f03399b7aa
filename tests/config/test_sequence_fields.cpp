// The simulator's sequence files on one field list (sim/sequence_fields.hpp): every member of
// SequenceConfig holds a key of the list, and every key, set to a value other than its default,
// reads back through SequenceConfigYaml + LoadSequenceConfig.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "dorado/io/field_yaml.hpp"
#include "dorado/sim/sequence_config.hpp"
#include "dorado/sim/sequence_fields.hpp"
#include "dorado/testing/field_coverage.hpp"
#include "dorado/testing/field_perturb.hpp"

namespace dorado::sim {
namespace {

TEST(SequenceFields, EveryMemberIsAField) {
    SequenceConfig config;
    // source_path: the file it came from, not a key.
    EXPECT_EQ(testing::MembersWithoutField(config, {&config.source_path}),
              std::vector<std::string>{});
}

TEST(SequenceFields, EveryKeyReadsBackAValueOtherThanItsDefault) {
    SequenceConfig changed;
    VisitFields(changed, testing::Perturb{});
    const std::string path = ::testing::TempDir() + "sequence_changed.yaml";
    std::ofstream(path) << SequenceConfigYaml(changed);
    const auto defaults = io::ListFields(SequenceConfig{});
    const auto expected = io::ListFields(changed);
    const auto actual = io::ListFields(LoadSequenceConfig(path));
    ASSERT_EQ(actual.size(), expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) {
        EXPECT_NE(expected[i].value, defaults[i].value) << expected[i].key;
        EXPECT_EQ(actual[i].key, expected[i].key);
        EXPECT_EQ(actual[i].value, expected[i].value) << "key '" << actual[i].key << "'";
    }
}

TEST(SequenceFields, PrintedDefaultsReadBackAsTheDefaults) {
    const std::string path = ::testing::TempDir() + "sequence_defaults.yaml";
    std::ofstream(path) << SequenceConfigYaml(SequenceConfig{});
    const auto actual = io::ListFields(LoadSequenceConfig(path));
    const auto expected = SequenceConfigFields();
    ASSERT_EQ(actual.size(), expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i)
        EXPECT_EQ(actual[i].value, expected[i].value) << actual[i].key;
}

TEST(SequenceFields, ErrorsNameTheFileAndTheKey) {
    const std::string path = ::testing::TempDir() + "sequence_bad.yaml";
    std::ofstream(path) << "radar:\n  mount: {translation_m: [1, 2]}\n";
    try {
        (void)LoadSequenceConfig(path);
        ADD_FAILURE() << "no error";
    } catch (const SequenceConfigError &e) {
        EXPECT_NE(std::string(e.what()).find(path + ": key 'radar.mount.translation_m'"),
                  std::string::npos)
            << e.what();
    }
    std::ofstream(path) << "motion: {speed_mp: 1}\n";
    EXPECT_THROW((void)LoadSequenceConfig(path), SequenceConfigError);
}

}  // namespace
}  // namespace dorado::sim
