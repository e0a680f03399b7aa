// The measured tables the pages quote are the generated files' (benchmarks/real/run_real.sh writes
// docs/generated/real_recordings.md): every `<!-- quoted from generated/FILE: NAME -->` block of a
// docs/*.md page holds exactly the table `<!-- table NAME -->` of docs/generated/FILE, and every
// page that prints measured real-recording numbers quotes them (no hand-copied table).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path kDocs = fs::path(DORADO_SOURCE_DIR) / "docs";

std::string Slurp(const fs::path &path) {
    std::ifstream in(path);
    if (!in) ADD_FAILURE() << path << ": cannot open";
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// NAME -> the text between `<!-- table NAME -->\n` and `<!-- end table -->`.
std::map<std::string, std::string> GeneratedTables(const fs::path &file) {
    std::map<std::string, std::string> tables;
    const std::string text = Slurp(file);
    const std::string open = "<!-- table ", close = "<!-- end table -->";
    for (std::size_t at = text.find(open); at != std::string::npos; at = text.find(open, at)) {
        const std::size_t name_end = text.find(" -->\n", at);
        const std::size_t body = name_end + 5;
        const std::size_t end = text.find(close, body);
        if (name_end == std::string::npos || end == std::string::npos) {
            ADD_FAILURE() << file << ": a table without its end marker";
            break;
        }
        tables[text.substr(at + open.size(), name_end - at - open.size())] =
            text.substr(body, end - body);
        at = end;
    }
    return tables;
}

struct Quote {
    std::string file, name, body;
};

std::vector<Quote> Quotes(const std::string &page) {
    std::vector<Quote> quotes;
    const std::regex block(
        "<!-- quoted from generated/(\\S+): (\\S+) -->\n([\\s\\S]*?)<!-- end quote -->");
    for (std::sregex_iterator it(page.begin(), page.end(), block), end; it != end; ++it)
        quotes.push_back({(*it)[1], (*it)[2], (*it)[3]});
    return quotes;
}

TEST(QuotedTables, EveryQuotedTableIsTheGeneratedOne) {
    std::size_t checked = 0;
    for (const auto &entry : fs::directory_iterator(kDocs)) {
        if (entry.path().extension() != ".md") continue;
        for (const Quote &q : Quotes(Slurp(entry.path()))) {
            const fs::path generated = kDocs / "generated" / q.file;
            ASSERT_TRUE(fs::exists(generated)) << entry.path() << " quotes " << generated;
            const auto tables = GeneratedTables(generated);
            const auto found = tables.find(q.name);
            ASSERT_NE(found, tables.end()) << entry.path() << " quotes table " << q.name
                                           << ", which " << generated << " does not hold";
            EXPECT_EQ(q.body, found->second)
                << entry.path().filename() << " quotes " << q.file << ": " << q.name
                << " unlike the generated file: run benchmarks/real/doc_tables.py quote "
                << "docs/generated/" << q.file << " docs/*.md, or regenerate with "
                << "benchmarks/real/run_real.sh";
            ++checked;
        }
    }
    EXPECT_GE(checked, 14u) << "the pages quote their measured tables";
}

TEST(QuotedTables, RealRecordingPagesQuoteTheirMeasuredTables) {
    // A table of measured runs on these pages is a quoted one: a hand-copied table (a `| run |`
    // header outside a quote block) is what let the pages disagree.
    for (const char *page : {"real_recordings.md", "multi_radar.md"}) {
        std::string text = Slurp(kDocs / page);
        text = std::regex_replace(text, std::regex("<!-- quoted from [\\s\\S]*?<!-- end quote -->"),
                                  "");
        EXPECT_EQ(text.find("| run |"), std::string::npos) << page << ": a table not quoted";
        EXPECT_EQ(text.find("| what | measured |"), std::string::npos)
            << page << ": a table not quoted";
    }
}

// A page's table with a measured number (a decimal outside `code`) that is neither quoted from a
// generated file nor a record of a decision (`<!-- record: ... -->`, naming how it was measured) is
// a hand-typed number that goes stale. Empty, if so: the tables that break the rule.
std::vector<std::string> UnquotedMeasuredTables(std::string page) {
    for (const char *block : {"<!-- quoted from [\\s\\S]*?<!-- end quote -->",
                              "<!-- record: [\\s\\S]*?<!-- end record -->", "```[\\s\\S]*?```"})
        page = std::regex_replace(page, std::regex(block), "");
    std::vector<std::string> found;
    std::istringstream lines(page);
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind("|", 0) != 0) continue;
        const std::string text = std::regex_replace(line, std::regex("`[^`]*`"), "");
        if (std::regex_search(text, std::regex("\\d\\.\\d"))) found.push_back(line);
    }
    return found;
}

TEST(QuotedTables, EveryMeasuredTableOfAPageIsQuotedOrARecord) {
    std::size_t pages = 0;
    for (const auto &entry : fs::directory_iterator(kDocs)) {
        const std::string name = entry.path().filename().string();
        // config_keys.md is `dorado config keys`' output (its defaults, not measurements).
        if (entry.path().extension() != ".md" || name == "config_keys.md") continue;
        for (const std::string &row : UnquotedMeasuredTables(Slurp(entry.path())))
            ADD_FAILURE() << name << ": a measured table neither quoted from docs/generated/ nor a "
                          << "record: " << row;
        ++pages;
    }
    EXPECT_GE(pages, 10u);
}

TEST(QuotedTables, ATypedTableBesideAQuotedOneIsFound) {
    const std::string page =
        "<!-- quoted from generated/g.md: t -->\n| a |\n|---|\n| 0.526 |\n<!-- end quote -->\n"
        "| setting | default |\n|---|---|\n| `lag_s` | `1.0` |\n"
        "<!-- record: by `x` -->\n| b |\n|---|\n| 1.5 |\n<!-- end record -->\n"
        "| map ATE | 0.131 m |\n";
    EXPECT_EQ(UnquotedMeasuredTables(page), std::vector<std::string>{"| map ATE | 0.131 m |"});
}

// The check itself: a quote that differs from its table by one digit is caught.
TEST(QuotedTables, OneDigitChangedIsADisagreement) {
    const fs::path dir = fs::path(::testing::TempDir()) / "dorado_quoted_tables";
    fs::create_directories(dir);
    std::ofstream(dir / "g.md")
        << "<!-- table t -->\n| a |\n|---|\n| 0.526 |\n<!-- end table -->\n";
    const auto tables = GeneratedTables(dir / "g.md");
    const auto quotes = Quotes(
        "x\n<!-- quoted from generated/g.md: t -->\n| a |\n|---|\n| 0.202 |\n"
        "<!-- end quote -->\n");
    ASSERT_EQ(quotes.size(), 1u);
    ASSERT_EQ(tables.count("t"), 1u);
    EXPECT_NE(quotes[0].body, tables.at("t"));
    EXPECT_EQ(tables.at("t"), "| a |\n|---|\n| 0.526 |\n");
    fs::remove_all(dir);
}

}  // namespace
