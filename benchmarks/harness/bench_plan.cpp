#include "bench_plan.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "bench_fields.hpp"
#include "dorado/config/map_config.hpp"
#include "dorado/config/odometry_config.hpp"
#include "dorado/io/dataset_config.hpp"
#include "dorado/io/field_yaml.hpp"

namespace dorado::apps {

namespace fs = std::filesystem;

namespace {

// One entry of `sequences:`, by BenchSequence's field list.
BenchSequence ParseSequence(const YAML::Node &node, std::size_t index, const std::string &base_dir,
                            const std::string &data_root, const std::string &origin) {
    io::FieldReader in(io::YamlSection(node, origin, "sequences[" + std::to_string(index) + "]"),
                       base_dir);
    BenchSequence s;
    VisitFields(s, in);
    // A misspelled key is reported before the checks that it would make fail.
    in.RejectUnknownKeys();
    if (s.name.empty() || s.name.find_first_of("/\\ @") != std::string::npos)
        in.Fail("name", "must be a non-empty name without '/', '@' or spaces");
    if (in.Has("simulate")) {
        if (!(s.duration_s >= 0.0) || !std::isfinite(s.duration_s))
            in.Fail("simulate.duration_s", "must be >= 0 (0: the simulator's default)");
        if (s.simulate_sequence.empty()) s.simulate_sequence = s.name;
        // A sequence file given relative to the config.
        if (s.simulate_sequence.size() > 5 &&
            s.simulate_sequence.substr(s.simulate_sequence.size() - 5) == ".yaml")
            s.simulate_sequence = io::ResolvePath(s.simulate_sequence, base_dir);
        s.dataset.clear();  // simulated: the simulation's dataset.yaml
        s.ground_truth.clear();
        s.data.clear();
    } else {
        s.simulate_sequence.clear();
        if (s.dataset.empty()) in.Fail("dataset", "a sequence needs `simulate:` or `dataset:`");
        s.data = io::ResolvePath(s.data, data_root);
        const std::string ext = fs::path(s.dataset).extension().string();
        if (s.ground_truth.empty() && (ext == ".yaml" || ext == ".yml")) {
            std::error_code ec;
            if (!s.data.empty() && !fs::is_directory(s.data, ec))
                in.Fail("data", s.data + ": no such folder (relative paths taken from " +
                                    data_root + ": change data:, data_dir: or --data DIR)");
            try {  // the description's reference, its path resolved as the runs resolve it
                s.ground_truth = io::LoadDatasetConfig(s.dataset, s.data).ground_truth.path;
            } catch (const std::exception &e) {
                in.Fail("dataset", e.what());
            }
        }
        if (s.ground_truth.empty())
            in.Fail("ground_truth", "is required: " + s.dataset + " names no ground_truth.path");
    }
    return s;
}

// grid.<kind>: {dotted.key: [v1, v2], ...}; values are scalars without '/', ',' or '@'.
std::vector<GridAxis> ParseGrid(io::YamlSection &grid, const YAML::Node &node,
                                const std::string &kind) {
    std::vector<GridAxis> axes;
    if (!grid.Has(kind)) return axes;
    if (!node.IsMap()) grid.Fail(kind, "must map config keys to lists of values");
    for (const auto &entry : node) {
        GridAxis axis{entry.first.as<std::string>(), {}};
        const std::string key = kind + "." + axis.key;
        if (!entry.second.IsSequence() || entry.second.size() == 0) {
            grid.Fail(key, "must be a non-empty list of values");
        }
        for (const auto &value : entry.second) {
            if (!value.IsScalar()) grid.Fail(key, "values must be numbers, words or booleans");
            axis.values.push_back(value.Scalar());
            if (axis.values.back().find_first_of("/\\,@ ") != std::string::npos) {
                grid.Fail(key, "value '" + axis.values.back() +
                                   "' names a directory: no '/', ',', '@' or spaces");
            }
        }
        // The key must be one the settings file reads (its field list), before any run starts.
        const auto fields =
            kind == "odometry" ? config::OdometryConfigFields() : config::MapConfigFields();
        bool known = false;
        for (const auto &field : fields) known |= field.key == axis.key;
        if (!known)
            grid.Fail(key, "is not a " + kind + " settings key (`dorado config keys` lists them)");
        axes.push_back(std::move(axis));
    }
    return axes;
}

// A bench measures every run, plausible or not: summary.json's "implausible" says which are not.
constexpr const char *kAcceptImplausible = "--accept-implausible";

// A run's arguments with --data DIR when its sequence names a data folder.
std::vector<std::string> WithData(std::vector<std::string> args, const std::string &data) {
    if (!data.empty()) {
        args.push_back("--data");
        args.push_back(data);
    }
    return args;
}

std::string FormatNumber(double value) {
    std::ostringstream os;
    os << value;
    return os.str();
}

}  // namespace

BenchConfig ParseBenchConfig(const std::string &yaml_text, const std::string &base_dir,
                             const std::string &origin, const std::string &data_dir) {
    YAML::Node node;
    try {
        node = YAML::Load(yaml_text);
    } catch (const YAML::Exception &e) {
        throw std::runtime_error(origin + ": not valid YAML: " + e.what());
    }
    if (!node.IsMap()) throw std::runtime_error(origin + ": expected a YAML mapping");
    io::FieldReader root(io::YamlSection(node, origin), base_dir);
    BenchConfig config;
    if (!root.Has("sequences") || !node["sequences"].IsSequence() ||
        node["sequences"].size() == 0) {
        root.Fail("sequences", "a non-empty list of sequences is required");
    }
    // The sequences' data: are taken from --data DIR, else data_dir:, else this file's folder.
    root("data_dir", config.data_dir, kPath, "");
    const std::string data_root = !data_dir.empty()
                                      ? io::ResolvePath(fs::absolute(data_dir).string(), "")
                                  : !config.data_dir.empty() ? config.data_dir
                                                             : base_dir;
    std::set<std::string> names;
    for (std::size_t i = 0; i < node["sequences"].size(); ++i) {
        config.sequences.push_back(
            ParseSequence(node["sequences"][i], i, base_dir, data_root, origin));
        if (!names.insert(config.sequences.back().name).second) {
            root.Fail("sequences[" + std::to_string(i) + "].name",
                      "repeats '" + config.sequences.back().name + "'");
        }
    }
    if (root.Has("jobs") && root.Section("").Get<std::int64_t>("jobs", 0) < 0)
        root.Fail("jobs", "must be >= 0 (0: the number of cores)");
    VisitFields(config, root);
    io::YamlSection &grid = root.Section("grid");
    if (root.Has("grid")) {
        const YAML::Node grid_node = node["grid"];
        config.odometry_grid = ParseGrid(grid, grid_node["odometry"], "odometry");
        config.map_grid = ParseGrid(grid, grid_node["map"], "map");
    }
    root.RejectUnknownKeys();
    for (const auto &[key, value] :
         {std::pair<const char *, double>{"association_max_gap_s", config.association_max_gap_s},
          {"t_max_diff_s", config.t_max_diff_s},
          {"rpe_second_delta_s", config.rpe_second_delta_s}}) {
        if (!(std::isfinite(value) && value > 0.0))
            root.Fail(key, "must be a positive number, got " + std::to_string(value));
    }
    if (config.rpe_frame_delta < 1) root.Fail("rpe_frame_delta", "must be >= 1");
    return config;
}

std::vector<io::FieldRow> BenchConfigFields() {
    auto rows = io::ListFields(BenchConfig{});
    for (const auto &row : io::ListFields(BenchSequence{}, "sequences[].")) rows.push_back(row);
    return rows;
}

BenchConfig LoadBenchConfig(const std::string &path, const std::string &data_dir) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot open the benchmark configuration");
    std::stringstream text;
    text << in.rdbuf();
    return ParseBenchConfig(text.str(), fs::path(path).parent_path().string(), path, data_dir);
}

void CheckBenchInputs(const BenchConfig &config) {
    const auto require = [](const std::string &path, const std::string &what) {
        std::error_code ec;
        if (!path.empty() && !fs::exists(path, ec))
            throw std::runtime_error(what + ": " + path + ": no such file or folder");
    };
    require(config.odometry_config, "odometry_config");
    require(config.map_config, "map_config");
    for (const BenchSequence &seq : config.sequences) {
        if (!seq.simulate_sequence.empty()) continue;
        const std::string where = "sequence '" + seq.name + "'";
        std::error_code ec;
        if (!seq.data.empty() && !fs::is_directory(seq.data, ec))
            throw std::runtime_error(where + ": data: " + seq.data + ": no such folder");
        try {
            (void)io::ResolveDataset(seq.dataset, seq.data);  // every path the runs will open
        } catch (const std::exception &e) {
            throw std::runtime_error(where + ": " + e.what());
        }
        require(seq.ground_truth, where + ": ground_truth");
    }
}

void WriteVariantConfigs(const BenchConfig &config, const std::string &out_dir) {
    for (const GridVariant &v : GridVariants(config.odometry_grid)) {
        if (!v.name.empty())
            WriteVariantConfig(config.odometry_config, v,
                               VariantConfigPath(out_dir, "odometry", v));
    }
    for (const GridVariant &v : GridVariants(config.map_grid)) {
        if (!v.name.empty())
            WriteVariantConfig(config.map_config, v, VariantConfigPath(out_dir, "map", v));
    }
}

BenchReference ParseBenchReference(const std::string &text) {
    if (text == "ground_truth") return BenchReference::kGroundTruth;
    if (text == "exact") return BenchReference::kExact;
    throw std::invalid_argument("must be ground_truth or exact, got '" + text + "'");
}

std::vector<BenchRun> PlanBenchmark(const BenchConfig &config, const std::string &out_dir) {
    const fs::path out(out_dir);
    std::vector<BenchRun> runs;
    for (const BenchSequence &seq : config.sequences) {
        std::string dataset = seq.dataset;
        std::string ground_truth = seq.ground_truth;
        std::vector<std::size_t> depends_on;
        if (config.reference == BenchReference::kExact && seq.simulate_sequence.empty()) {
            throw std::runtime_error("sequence '" + seq.name +
                                     "': the exact reference needs a simulated sequence (this "
                                     "one is recorded data: score it with reference: "
                                     "ground_truth)");
        }
        if (!seq.simulate_sequence.empty()) {
            const fs::path data_dir = out / "data" / seq.name;
            dataset = (data_dir / "dataset.yaml").string();
            ground_truth =
                (data_dir / (config.reference == BenchReference::kExact ? "true_trajectory.tum"
                                                                        : "ground_truth.tum"))
                    .string();
            BenchRun sim{RunKind::kSimulate, seq.name, "simulate", dataset, ground_truth, true, {}};
            sim.job = {seq.name + "/simulate",
                       data_dir.string(),
                       "simulation.json",
                       {"simulate", "--sequence", seq.simulate_sequence, "--out", "{out}", "--seed",
                        std::to_string(seq.seed)},
                       {}};
            if (seq.duration_s > 0.0) {
                sim.job.args.push_back("--duration");
                sim.job.args.push_back(FormatNumber(seq.duration_s));
            }
            depends_on.push_back(runs.size());
            runs.push_back(sim);
        }
        const auto add_run = [&](RunKind kind, const std::string &method,
                                 std::vector<std::string> args, const std::string &run_config,
                                 bool has_translation = true) {
            if (!run_config.empty()) {
                args.push_back("--config");
                args.push_back(run_config);
            }
            BenchRun run{kind, seq.name, method, dataset, ground_truth, has_translation, {}};
            run.job = {seq.name + "/" + method, (out / "runs" / seq.name / method).string(),
                       "summary.json", std::move(args), depends_on};
            runs.push_back(std::move(run));
        };
        for (const GridVariant &variant : GridVariants(config.odometry_grid)) {
            const std::string run_config = variant.name.empty()
                                               ? config.odometry_config
                                               : VariantConfigPath(out_dir, "odometry", variant);
            const std::string suffix = variant.name.empty() ? "" : "@" + variant.name;
            for (const odometry::OdometryMethod m :
                 seq.odometry_methods.value_or(config.odometry_methods)) {
                // The paper's three: gyro-only rotation ("IMU"), Doppler only, IMU + Doppler.
                add_run(RunKind::kOdometry, std::string("odom_") + ToString(m) + suffix,
                        WithData({"odometry", dataset, "--out", "{out}", kAcceptImplausible,
                                  "--method", ToString(m)},
                                 seq.data),
                        run_config, m != odometry::OdometryMethod::kImu);
            }
        }
        for (const GridVariant &variant : GridVariants(config.map_grid)) {
            const std::string run_config = variant.name.empty()
                                               ? config.map_config
                                               : VariantConfigPath(out_dir, "map", variant);
            const std::string suffix = variant.name.empty() ? "" : "@" + variant.name;
            for (const mapping::PriorKind prior : seq.map_priors.value_or(config.map_priors)) {
                add_run(RunKind::kMap, std::string("map_") + ToString(prior) + suffix,
                        WithData({"map", dataset, "--prior", ToString(prior), "--out", "{out}",
                                  kAcceptImplausible},
                                 seq.data),
                        run_config);
            }
        }
    }
    return runs;
}

}  // namespace dorado::apps
