// The bench file on field lists (benchmarks/harness/bench_fields.hpp): every member of BenchConfig
// and BenchSequence holds a key of its list (but the lists of their own: sequences, grids), and
// every key, set to a value other than its default, reads back through ParseBenchConfig.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "bench_fields.hpp"
#include "bench_plan.hpp"
#include "dorado/io/field_yaml.hpp"
#include "dorado/testing/field_coverage.hpp"
#include "dorado/testing/field_perturb.hpp"

namespace dorado::apps {
namespace {

TEST(BenchFields, EveryMemberIsAField) {
    BenchConfig config;
    // sequences: a list, each entry BenchSequence's list; grids: config keys to lists of values.
    EXPECT_EQ(testing::MembersWithoutField(
                  config, {&config.sequences, &config.odometry_grid, &config.map_grid}),
              std::vector<std::string>{});
    BenchSequence sequence;
    EXPECT_EQ(testing::MembersWithoutField(sequence, {}), std::vector<std::string>{});
}

/// Forwards the fields but those whose key starts with one of @p skip.
struct Skipping {
    std::vector<std::string> skip;
    io::FieldWriter &writer;

    bool Skips(const std::string &key) const {
        for (const auto &prefix : skip)
            if (key.rfind(prefix, 0) == 0) return true;
        return false;
    }
    template <typename T>
    void operator()(const char *key, T &member, const char *doc) const {
        if (!Skips(key)) writer(key, member, doc);
    }
    template <typename T, typename Extra>
    void operator()(const char *key, T &member, const Extra &extra, const char *doc) const {
        if (!Skips(key)) writer(key, member, extra, doc);
    }
};

std::string Text(const std::vector<io::FieldRow> &rows) {
    std::string text;
    for (const auto &row : rows) text += row.key + ": " + row.value + "\n";
    return text;
}

TEST(BenchFields, EveryKeyReadsBackAValueOtherThanItsDefault) {
    BenchConfig changed;
    VisitFields(changed, testing::Perturb{});
    // A simulated sequence and a recorded one: each key of an entry is in one of them.
    BenchSequence simulated;
    VisitFields(simulated, testing::Perturb{});
    simulated.dataset.clear();
    simulated.data.clear();
    simulated.ground_truth.clear();
    BenchSequence recorded;
    VisitFields(recorded, testing::Perturb{});
    recorded.name += "_recorded";
    recorded.simulate_sequence.clear();
    recorded.seed = BenchSequence{}.seed;
    recorded.duration_s = BenchSequence{}.duration_s;
    recorded.data = "/perturbed/recorded_data";  // absolute: kept as written, not under data_dir
    changed.sequences = {simulated, recorded};

    io::FieldWriter writer;
    VisitFields(changed, writer);
    std::vector<std::string> items;
    for (BenchSequence &sequence : changed.sequences) {
        io::FieldWriter item;
        const bool is_simulated = !sequence.simulate_sequence.empty();
        VisitFields(sequence,
                    Skipping{is_simulated ? std::vector<std::string>{"data", "ground_truth"}
                                          : std::vector<std::string>{"simulate."},
                             item});
        items.push_back(item.text());
    }
    writer.AddList("sequences", items, "the sequences");
    const BenchConfig back = ParseBenchConfig(writer.text(), "/base", "changed.yaml");

    const auto defaults = io::ListFields(BenchConfig{});
    const auto expected = io::ListFields(changed);
    for (std::size_t i = 0; i < expected.size(); ++i)
        EXPECT_NE(expected[i].value, defaults[i].value) << expected[i].key;
    EXPECT_EQ(Text(io::ListFields(back)), Text(expected));
    ASSERT_EQ(back.sequences.size(), 2u);
    const auto sequence_defaults = io::ListFields(BenchSequence{});
    std::vector<bool> differs(sequence_defaults.size(), false);
    for (std::size_t k = 0; k < 2; ++k) {
        const auto rows = io::ListFields(changed.sequences[k]);
        EXPECT_EQ(Text(io::ListFields(back.sequences[k])), Text(rows));
        for (std::size_t i = 0; i < rows.size(); ++i)
            differs[i] = differs[i] || rows[i].value != sequence_defaults[i].value;
    }
    for (std::size_t i = 0; i < differs.size(); ++i)
        EXPECT_TRUE(differs[i]) << "sequences[]." << sequence_defaults[i].key;
}

}  // namespace
}  // namespace dorado::apps
