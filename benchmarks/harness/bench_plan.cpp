#include "bench_plan.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "dorado/io/yaml_section.hpp"

namespace dorado::apps {

namespace fs = std::filesystem;

namespace {

const std::vector<std::string> kOdometryMethods{"imu", "doppler", "imu+doppler"};
const std::vector<std::string> kMapPriors{"none", "constvel", "imu", "doppler", "imu+doppler"};

[[noreturn]] void Fail(const std::string &origin, const std::string &key, const std::string &what) {
    throw std::runtime_error(origin + ": " + key + ": " + what);
}

std::string Resolve(const std::string &base_dir, const std::string &path) {
    if (path.empty() || fs::path(path).is_absolute()) return path;
    return (fs::path(base_dir) / path).lexically_normal().string();
}

template <typename T>
T Get(const YAML::Node &node, const std::string &key, const T &fallback, const std::string &origin,
      const std::string &where) {
    if (!node[key]) return fallback;
    try {
        return node[key].as<T>();
    } catch (const YAML::Exception &) {
        Fail(origin, where + key, "has the wrong type");
    }
}

std::vector<std::string> GetMethods(const YAML::Node &root, const std::string &key,
                                    const std::vector<std::string> &allowed,
                                    const std::string &origin) {
    const auto methods = Get<std::vector<std::string>>(root, key, allowed, origin, "");
    for (const std::string &m : methods) {
        if (std::find(allowed.begin(), allowed.end(), m) == allowed.end()) {
            std::string list;
            for (const auto &a : allowed) list += (list.empty() ? "" : ", ") + a;
            Fail(origin, key, "unknown method '" + m + "' (expected one of: " + list + ")");
        }
    }
    return methods;
}

// A misspelled key must not silently fall back to a default: dorado_io's strict section
// reports the first unknown key with the nearest known one.
void RejectUnknownKeys(const YAML::Node &node, std::initializer_list<const char *> known,
                       const std::string &origin, const std::string &where) {
    io::YamlSection section(node, origin, where);
    for (const char *key : known) (void)section.Has(key);
    section.RejectUnknownKeys();
}

BenchSequence ParseSequence(const YAML::Node &node, std::size_t index, const std::string &base_dir,
                            const std::string &origin) {
    const std::string where = "sequences[" + std::to_string(index) + "].";
    BenchSequence s;
    s.name = Get<std::string>(node, "name", "", origin, where);
    if (s.name.empty() || s.name.find_first_of("/\\ ") != std::string::npos) {
        Fail(origin, where + "name", "must be a non-empty name without '/' or spaces");
    }
    RejectUnknownKeys(node, {"name", "simulate", "dataset", "ground_truth"}, origin,
                      where.substr(0, where.size() - 1));
    if (node["simulate"]) {
        const YAML::Node sim = node["simulate"];
        const std::string sim_where = where + "simulate.";
        RejectUnknownKeys(sim, {"sequence", "seed", "duration_s"}, origin,
                          sim_where.substr(0, sim_where.size() - 1));
        s.simulate_sequence = Get<std::string>(sim, "sequence", s.name, origin, sim_where);
        s.seed = Get<int64_t>(sim, "seed", 1, origin, sim_where);
        s.duration_s = Get<double>(sim, "duration_s", 0.0, origin, sim_where);
        if (!(s.duration_s >= 0.0) || !std::isfinite(s.duration_s)) {
            Fail(origin, sim_where + "duration_s", "must be >= 0 (0: the simulator's default)");
        }
        // A sequence file given relative to the config.
        if (s.simulate_sequence.size() > 5 &&
            s.simulate_sequence.substr(s.simulate_sequence.size() - 5) == ".yaml") {
            s.simulate_sequence = Resolve(base_dir, s.simulate_sequence);
        }
    } else {
        s.dataset = Resolve(base_dir, Get<std::string>(node, "dataset", "", origin, where));
        s.ground_truth =
            Resolve(base_dir, Get<std::string>(node, "ground_truth", "", origin, where));
        if (s.dataset.empty() || s.ground_truth.empty()) {
            Fail(origin, where + "dataset",
                 "a sequence needs `simulate:` or both `dataset:` and "
                 "`ground_truth:`");
        }
    }
    return s;
}

std::string FormatNumber(double value) {
    std::ostringstream os;
    os << value;
    return os.str();
}

}  // namespace

BenchConfig ParseBenchConfig(const std::string &yaml_text, const std::string &base_dir,
                             const std::string &origin) {
    YAML::Node root;
    try {
        root = YAML::Load(yaml_text);
    } catch (const YAML::Exception &e) {
        throw std::runtime_error(origin + ": not valid YAML: " + e.what());
    }
    if (!root.IsMap()) throw std::runtime_error(origin + ": expected a YAML mapping");
    RejectUnknownKeys(
        root,
        {"sequences", "odometry", "map_priors", "odometry_config", "map_config", "jobs",
         "association_max_gap_s", "rpe_frame_delta", "rpe_second_delta_s", "reference"},
        origin, "");
    BenchConfig config;
    if (!root["sequences"] || !root["sequences"].IsSequence() || root["sequences"].size() == 0) {
        Fail(origin, "sequences", "a non-empty list of sequences is required");
    }
    std::set<std::string> names;
    for (std::size_t i = 0; i < root["sequences"].size(); ++i) {
        config.sequences.push_back(ParseSequence(root["sequences"][i], i, base_dir, origin));
        if (!names.insert(config.sequences.back().name).second) {
            Fail(origin, "sequences[" + std::to_string(i) + "].name",
                 "repeats '" + config.sequences.back().name + "'");
        }
    }
    config.odometry_methods = GetMethods(root, "odometry", kOdometryMethods, origin);
    config.map_priors = GetMethods(root, "map_priors", kMapPriors, origin);
    config.odometry_config =
        Resolve(base_dir, Get<std::string>(root, "odometry_config", "", origin, ""));
    config.map_config = Resolve(base_dir, Get<std::string>(root, "map_config", "", origin, ""));
    const int jobs = Get<int>(root, "jobs", 0, origin, "");
    if (jobs < 0) Fail(origin, "jobs", "must be >= 0 (0: the number of cores)");
    config.jobs = static_cast<std::size_t>(jobs);
    config.association_max_gap_s =
        Get<double>(root, "association_max_gap_s", config.association_max_gap_s, origin, "");
    if (!(config.association_max_gap_s > 0.0)) Fail(origin, "association_max_gap_s", "must be > 0");
    config.rpe_frame_delta = Get<int>(root, "rpe_frame_delta", config.rpe_frame_delta, origin, "");
    if (config.rpe_frame_delta < 1) Fail(origin, "rpe_frame_delta", "must be >= 1");
    config.rpe_second_delta_s =
        Get<double>(root, "rpe_second_delta_s", config.rpe_second_delta_s, origin, "");
    if (!(config.rpe_second_delta_s > 0.0)) Fail(origin, "rpe_second_delta_s", "must be > 0");
    try {
        config.reference =
            ParseBenchReference(Get<std::string>(root, "reference", "ground_truth", origin, ""));
    } catch (const std::invalid_argument &e) {
        Fail(origin, "reference", e.what());
    }
    return config;
}

BenchConfig LoadBenchConfig(const std::string &path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot open the benchmark configuration");
    std::stringstream text;
    text << in.rdbuf();
    return ParseBenchConfig(text.str(), fs::path(path).parent_path().string(), path);
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
            BenchRun sim{RunKind::kSimulate, seq.name, "simulate", dataset, ground_truth, {}};
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
                                 std::vector<std::string> args, const std::string &run_config) {
            if (!run_config.empty()) {
                args.push_back("--config");
                args.push_back(run_config);
            }
            BenchRun run{kind, seq.name, method, dataset, ground_truth, {}};
            run.job = {seq.name + "/" + method, (out / "runs" / seq.name / method).string(),
                       "summary.json", std::move(args), depends_on};
            runs.push_back(std::move(run));
        };
        for (const std::string &m : config.odometry_methods) {
            // The paper's three: gyro-only rotation ("IMU"), Doppler only, IMU + Doppler.
            add_run(RunKind::kOdometry, "odom_" + m,
                    {"odometry", dataset, "--out", "{out}", "--method", m},
                    config.odometry_config);
        }
        for (const std::string &prior : config.map_priors) {
            add_run(RunKind::kMap, "map_" + prior,
                    {"map", dataset, "--prior", prior, "--out", "{out}"}, config.map_config);
        }
    }
    return runs;
}

}  // namespace dorado::apps
