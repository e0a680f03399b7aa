// The shared YAML mapping reader of the config loaders: defaults, error texts, unknown keys.
#include "dorado/io/yaml_section.hpp"

#include <gtest/gtest.h>

#include <string>

namespace dorado::io {
namespace {

enum class Colour { kRed, kGreen, kBlue };

/// The message of the ConfigError that @p read throws (empty if it throws none).
template <typename Read>
std::string ErrorOf(Read read) {
    try {
        read();
    } catch (const ConfigError &e) {
        return e.what();
    }
    return "";
}

TEST(YamlSection, AbsentAndEmptyMeanDefaults) {
    YamlSection top(YAML::Load("a:\nb: {}\nc: 2.5\n"), "f.yaml");
    EXPECT_EQ(top.Get<int>("a", 7), 7) << "an empty value is the default";
    YamlSection b = top.Child("b");
    YamlSection missing = top.Child("missing");
    EXPECT_EQ(missing.Get<std::string>("x", "dflt"), "dflt");
    double c = 1.0;
    top.Read("c", c);
    EXPECT_EQ(c, 2.5);
    Eigen::Vector3d v(1, 2, 3);
    b.ReadVector3("v", v);
    EXPECT_EQ(v, Eigen::Vector3d(1, 2, 3));
    EXPECT_NO_THROW(b.RejectUnknownKeys());
    EXPECT_NO_THROW(missing.RejectUnknownKeys());
    EXPECT_NO_THROW(top.RejectUnknownKeys());
}

TEST(YamlSection, ErrorsNameFileDottedKeyAndLine) {
    YamlSection top(YAML::Load("s:\n  t:\n    n: wide\n    p: -1\n    v: [1, 2]\n"), "f.yaml");
    YamlSection t = top.Child("s").Child("t");
    EXPECT_EQ(ErrorOf([&] { (void)t.Get<double>("n", 0.0); }),
              "f.yaml: key 's.t.n': has the wrong type (line 3)");
    EXPECT_EQ(ErrorOf([&] { (void)t.GetPositive("p", 1.0); }),
              "f.yaml: key 's.t.p': must be a positive number, got -1.000000");
    Eigen::Vector3d v;
    EXPECT_EQ(ErrorOf([&] { t.ReadVector3("v", v); }), "f.yaml: key 's.t.v': must have 3 values");
    EXPECT_EQ(ErrorOf([&] { t.Fail("", "is odd"); }), "f.yaml: key 's.t': is odd");
    EXPECT_EQ(ErrorOf([&] { top.Fail("", "is odd"); }), "f.yaml: key '(top level)': is odd");
    EXPECT_EQ(ErrorOf([&] { YamlSection(YAML::Load("[1, 2]"), "f.yaml"); }),
              "f.yaml: key '(top level)': must be a mapping");
    EXPECT_EQ(ErrorOf([&] { (void)top.Child("s").Child("t").Child("n"); }),
              "f.yaml: key 's.t.n': must be a mapping");
}

TEST(YamlSection, EnumsByNameListTheNamesInOrder) {
    YamlSection top(YAML::Load("good: green\nbad: purple\n"), "f.yaml");
    const std::vector<std::pair<std::string, Colour>> names = {
        {"red", Colour::kRed}, {"green", Colour::kGreen}, {"blue", Colour::kBlue}};
    Colour colour = Colour::kRed;
    top.ReadEnum("good", colour, names);
    EXPECT_EQ(colour, Colour::kGreen);
    top.ReadEnum("absent", colour, names);
    EXPECT_EQ(colour, Colour::kGreen);
    EXPECT_EQ(ErrorOf([&] { top.ReadEnum("bad", colour, names); }),
              "f.yaml: key 'bad': must be red, green or blue, got 'purple'");
}

TEST(YamlSection, UnknownKeySuggestsTheNearestKnownOne) {
    YamlSection top(YAML::Load("max_rnage_m: 1\n"), "f.yaml");
    (void)top.Get<double>("min_range_m", 0.0);
    (void)top.Get<double>("max_range_m", 0.0);
    EXPECT_EQ(ErrorOf([&] { top.RejectUnknownKeys(); }),
              "f.yaml: key 'max_rnage_m': unknown key (did you mean 'max_range_m'?); known keys: "
              "max_range_m, min_range_m");
    YamlSection far(YAML::Load("zzz: 1\n"), "f.yaml");
    (void)far.Has("abc");
    EXPECT_EQ(ErrorOf([&] { far.RejectUnknownKeys(); }),
              "f.yaml: key 'zzz': unknown key; known keys: abc");
}

}  // namespace
}  // namespace dorado::io
