#include "bench_grid.hpp"

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "dorado/io/atomic_file.hpp"
#include "dorado/io/yaml_section.hpp"

namespace dorado::apps {

namespace fs = std::filesystem;

namespace {

std::string LastComponent(const std::string &dotted) {
    const std::size_t dot = dotted.rfind('.');
    return dot == std::string::npos ? dotted : dotted.substr(dot + 1);
}

// Sets root[a][b][c] = value for key "a.b.c", creating the mappings on the way.
void SetDotted(YAML::Node root, const std::string &key, const std::string &value,
               const std::string &path) {
    std::vector<std::string> parts;
    std::size_t begin = 0;
    while (true) {
        const std::size_t dot = key.find('.', begin);
        parts.push_back(key.substr(begin, dot - begin));
        if (dot == std::string::npos) break;
        begin = dot + 1;
    }
    std::vector<YAML::Node> chain{root};
    for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
        YAML::Node child = chain.back()[parts[i]];
        if (child.IsDefined() && !child.IsNull() && !child.IsMap()) {
            throw std::runtime_error(path + ": grid key '" + key + "': '" + parts[i] +
                                     "' is not a mapping in the base config");
        }
        chain.push_back(child);
    }
    chain.back()[parts.back()] = YAML::Load(value);
}

}  // namespace

std::vector<GridVariant> GridVariants(const std::vector<GridAxis> &axes) {
    std::vector<GridVariant> variants{GridVariant{}};
    for (const GridAxis &axis : axes) {
        std::vector<GridVariant> next;
        for (const GridVariant &v : variants) {
            for (const std::string &value : axis.values) {
                GridVariant point = v;
                point.name +=
                    (point.name.empty() ? "" : ",") + LastComponent(axis.key) + "=" + value;
                point.settings.emplace_back(axis.key, value);
                next.push_back(std::move(point));
            }
        }
        variants = std::move(next);
    }
    return variants;
}

std::string VariantConfigPath(const std::string &out_dir, const std::string &kind,
                              const GridVariant &variant) {
    return (fs::path(out_dir) / "configs" / (kind + "@" + variant.name + ".yaml")).string();
}

void WriteVariantConfig(const std::string &base_config, const GridVariant &variant,
                        const std::string &path) {
    YAML::Node root =
        base_config.empty() ? YAML::Node(YAML::NodeType::Map) : io::LoadYamlFile(base_config);
    if (root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
    if (!root.IsMap()) throw std::runtime_error(base_config + ": expected a YAML mapping");
    for (const auto &[key, value] : variant.settings) SetDotted(root, key, value, base_config);
    YAML::Emitter out;
    out << root;
    const std::string text = "# grid variant " + variant.name + " of " +
                             (base_config.empty() ? "the built-in defaults" : base_config) +
                             " (written by dorado bench)\n" + out.c_str() + "\n";
    // Unchanged files are left alone: on a cluster every job re-reads the plan (Snakemake parses
    // the Snakefile again in each job), and concurrent rewrites of one file would race.
    std::ifstream existing(path, std::ios::binary);
    if (existing) {
        const std::string current((std::istreambuf_iterator<char>(existing)),
                                  std::istreambuf_iterator<char>());
        if (current == text) return;
    }
    io::MakeDirectories(fs::path(path).parent_path().string());
    io::WriteFileAtomically(path, [&](std::ostream &os) { os << text; });
}

}  // namespace dorado::apps
