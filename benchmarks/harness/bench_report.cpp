// The benchmark report: results.csv, bench_runs.csv, rpe_pairs.csv and results.md from the runs
// evaluated by bench_evaluate.cpp.
#include "bench_report.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

#include "dorado/eval/association.hpp"
#include "dorado/io/atomic_file.hpp"
#include "dorado/io/csv_text.hpp"

namespace dorado::apps {

namespace fs = std::filesystem;

namespace {

// Statistics rows of the report: metric name, unit, and the values of a run.
struct Metric {
    const char *name;
    const char *unit;
    bool needs_translation;
    std::function<const std::vector<double> &(const RunEvaluation &)> Of;
};

const std::vector<Metric> &Metrics() {
    using E = RunEvaluation;
    using Values = std::vector<double>;
    static const std::vector<Metric> metrics{
        {"rpe_frame_translation", "m", true,
         [](const E &e) -> const Values & { return e.rpe_frame.translation_m; }},
        {"rpe_frame_rotation", "deg", false,
         [](const E &e) -> const Values & { return e.rpe_frame.rotation_deg; }},
        {"rpe_second_translation", "m", true,
         [](const E &e) -> const Values & { return e.rpe_second.translation_m; }},
        {"rpe_second_rotation", "deg", false,
         [](const E &e) -> const Values & { return e.rpe_second.rotation_deg; }},
        {"ate_translation", "m", true, [](const E &e) -> const Values & { return e.ate_m; }},
        {"time_per_scan", "ms", false,
         [](const E &e) -> const Values & { return e.time_per_scan_ms; }},
        {"rpe_frame_roll", "deg", false,
         [](const E &e) -> const Values & { return e.rpe_frame.roll_deg; }},
        {"rpe_frame_pitch", "deg", false,
         [](const E &e) -> const Values & { return e.rpe_frame.pitch_deg; }},
        {"rpe_frame_yaw", "deg", false,
         [](const E &e) -> const Values & { return e.rpe_frame.yaw_deg; }},
        {"rpe_second_roll", "deg", false,
         [](const E &e) -> const Values & { return e.rpe_second.roll_deg; }},
        {"rpe_second_pitch", "deg", false,
         [](const E &e) -> const Values & { return e.rpe_second.pitch_deg; }},
        {"rpe_second_yaw", "deg", false,
         [](const E &e) -> const Values & { return e.rpe_second.yaw_deg; }},
    };
    return metrics;
}

std::vector<double> Finite(const std::vector<double> &values) {
    std::vector<double> out;
    for (const double v : values) {
        if (std::isfinite(v)) out.push_back(v);
    }
    return out;
}

std::string Num(double value, int precision) {
    if (!std::isfinite(value)) return "—";
    std::ostringstream os;
    os << std::fixed << std::setprecision(precision) << value;
    return os.str();
}

void WriteStatisticsRow(std::ostream &os, const std::string &sequence, const std::string &method,
                        const Metric &metric, const std::vector<double> &values) {
    const eval::Statistics s = eval::ComputeStatistics(Finite(values));
    os << io::CsvCell(sequence) << ',' << io::CsvCell(method) << ',' << metric.name << ','
       << metric.unit << std::setprecision(9) << ',' << s.rmse << ',' << s.mean << ',' << s.median
       << ',' << s.std << ',' << s.min << ',' << s.max << ',' << s.count << '\n';
}

// Runs grouped by method, in first-seen order (the rows of a table).
std::vector<std::pair<std::string, std::vector<const RunEvaluation *>>> ByMethod(
    const std::vector<const RunEvaluation *> &rows) {
    std::vector<std::pair<std::string, std::vector<const RunEvaluation *>>> groups;
    for (const RunEvaluation *e : rows) {
        auto it = std::find_if(groups.begin(), groups.end(),
                               [&](const auto &g) { return g.first == e->method; });
        if (it == groups.end()) it = groups.insert(groups.end(), {e->method, {}});
        it->second.push_back(e);
    }
    return groups;
}

// Statistics of a metric over the pooled pairs of a group of runs.
eval::Statistics PooledStatistics(const std::vector<const RunEvaluation *> &group,
                                  const Metric &metric) {
    std::vector<double> values;
    for (const RunEvaluation *e : group) {
        if (!e->ok || (metric.needs_translation && !e->has_translation)) continue;
        const auto &v = metric.Of(*e);
        values.insert(values.end(), v.begin(), v.end());
    }
    return eval::ComputeStatistics(Finite(values));
}

// p95 of the pooled time per scan of a group of runs.
double PooledTimeP95(const std::vector<const RunEvaluation *> &group) {
    std::vector<double> t;
    for (const RunEvaluation *e : group)
        t.insert(t.end(), e->time_per_scan_ms.begin(), e->time_per_scan_ms.end());
    t = Finite(t);
    if (t.empty()) return std::numeric_limits<double>::quiet_NaN();
    std::sort(t.begin(), t.end());
    return t[static_cast<std::size_t>(0.95 * static_cast<double>(t.size() - 1))];
}

void WriteMarkdownTable(std::ostream &os, const std::vector<const RunEvaluation *> &rows,
                        bool pooled) {
    os << "| method | RPE/frame trans [m] | RPE/frame rot [deg] | RPE/s trans [m] | RPE/s rot "
          "[deg] | "
          "ATE rmse [m] | time/scan mean, median, p95 [ms] |"
       << (pooled ? "" : " poses scored |") << "\n";
    os << "|---|---:|---:|---:|---:|---:|---:|" << (pooled ? "" : "---:|") << "\n";
    // Rows of the same method are pooled (over sequences when `pooled`).
    for (const auto &[method, group] : ByMethod(rows)) {
        const auto stat = [&](const Metric &metric) { return PooledStatistics(group, metric); };
        const auto &m = Metrics();
        os << "| " << method << " | " << Num(stat(m[0]).mean, 3) << " | " << Num(stat(m[1]).mean, 3)
           << " | " << Num(stat(m[2]).mean, 3) << " | " << Num(stat(m[3]).mean, 3) << " | "
           << Num(stat(m[4]).rmse, 3) << " | " << Num(stat(m[5]).mean, 2) << ", "
           << Num(stat(m[5]).median, 2) << ", " << Num(PooledTimeP95(group), 2) << " |";
        if (!pooled) {
            const RunEvaluation &e = *group.front();
            os << ' '
               << (e.ok ? std::to_string(e.scored) + "/" + std::to_string(e.poses) : "failed")
               << " |";
        }
        os << "\n";
    }
}

// Where the rotation error lives: mean |roll|, |pitch|, |yaw| of the pairs' rotation errors.
void WriteAxisTable(std::ostream &os, const std::vector<const RunEvaluation *> &rows) {
    os << "| method | RPE/frame roll | pitch | yaw [deg] | RPE/s roll | pitch | yaw [deg] |\n"
       << "|---|---:|---:|---:|---:|---:|---:|\n";
    const auto &m = Metrics();
    for (const auto &[method, group] : ByMethod(rows)) {
        os << "| " << method;
        for (std::size_t k = 6; k < 12; ++k)
            os << " | " << Num(PooledStatistics(group, m[k]).mean, 3);
        os << " |\n";
    }
}

std::string FormatSeconds(double seconds) {
    std::ostringstream os;
    os << seconds << " s";
    return os.str();
}

// results.csv: statistics per sequence, method and metric, then over all sequences ("all").
void WriteResultsCsv(std::ostream &os, const std::vector<RunEvaluation> &evaluations) {
    os << "sequence,method,metric,unit,rmse,mean,median,std,min,max,count\n";
    std::map<std::string, std::map<std::string, std::vector<double>>> pooled;
    std::vector<std::string> methods;
    for (const RunEvaluation &e : evaluations) {
        if (!e.ok) continue;
        if (std::find(methods.begin(), methods.end(), e.method) == methods.end()) {
            methods.push_back(e.method);
        }
        for (const Metric &metric : Metrics()) {
            if (metric.needs_translation && !e.has_translation) continue;
            WriteStatisticsRow(os, e.sequence, e.method, metric, metric.Of(e));
            auto &all = pooled[e.method][metric.name];
            all.insert(all.end(), metric.Of(e).begin(), metric.Of(e).end());
        }
    }
    for (const std::string &method : methods) {
        for (const Metric &metric : Metrics()) {
            const auto it = pooled[method].find(metric.name);
            if (it != pooled[method].end())
                WriteStatisticsRow(os, "all", method, metric, it->second);
        }
    }
}

// bench_runs.csv: each run, its directory, ground truth, status and poses.
void WriteRunsCsv(std::ostream &os, const std::vector<RunEvaluation> &evaluations) {
    os << "sequence,method,run_dir,ground_truth,ok,poses,matched,scored,note\n";
    for (const RunEvaluation &e : evaluations) {
        std::string note = e.note;
        std::replace(note.begin(), note.end(), '\n', ' ');
        os << io::CsvCell(e.sequence) << ',' << io::CsvCell(e.method) << ','
           << io::CsvCell(e.run_dir) << ',' << io::CsvCell(e.ground_truth) << ',' << (e.ok ? 1 : 0)
           << ',' << e.poses << ',' << e.matched << ',' << e.scored << ',' << io::CsvCell(note)
           << '\n';
    }
}

// rpe_pairs.csv: every RPE pair, for the box plots.
void WriteRpePairsCsv(std::ostream &os, const std::vector<RunEvaluation> &evaluations) {
    os << "sequence,method,delta_unit,t_i,t_j,translation_m,rotation_deg,roll_deg,pitch_deg,"
          "yaw_deg\n"
       << std::setprecision(9);
    for (const RunEvaluation &e : evaluations) {
        const auto write = [&](const eval::RelativeErrors &rpe, const char *unit) {
            for (std::size_t p = 0; p < rpe.pairs.size(); ++p) {
                os << io::CsvCell(e.sequence) << ',' << io::CsvCell(e.method) << ',' << unit << ','
                   << std::fixed << std::setprecision(6) << rpe.stamp_i_ns[p] * 1e-9 << ','
                   << rpe.stamp_j_ns[p] * 1e-9 << std::defaultfloat << std::setprecision(9) << ','
                   << (e.has_translation ? rpe.translation_m[p] : std::nan("")) << ','
                   << rpe.rotation_deg[p] << ',' << rpe.roll_deg[p] << ',' << rpe.pitch_deg[p]
                   << ',' << rpe.yaw_deg[p] << '\n';
            }
        };
        write(e.rpe_frame, "frames");
        write(e.rpe_second, "seconds");
    }
}

// results.md: a table per sequence, the pooled table and the rotation error by body axis.
void WriteResultsMarkdown(std::ostream &os, const std::vector<RunEvaluation> &evaluations,
                          const BenchConfig &config) {
    os << "# dorado benchmark\n\n"
       << "RPE (mean over pairs) per frame (delta " << config.rpe_frame_delta << ") and per "
       << config.rpe_second_delta_s << " s, against "
       << (config.association == eval::AssociationMethod::kNearest
               ? "the ground truth pose with the nearest stamp within " +
                     FormatSeconds(config.t_max_diff_s) +
                     " of each estimated stamp (association: nearest, as evo's "
                     "associate_trajectories with --t_max_diff)"
               : "the ground truth interpolated at each estimated stamp (association: "
                 "interpolate, across gaps up to " +
                     FormatSeconds(config.association_max_gap_s) + ")")
       << " (reference: "
       << (config.reference == BenchReference::kExact
               ? "the simulator's exact trajectory, true_trajectory.tum"
               : "the ground truth as recorded, ground_truth.tum for simulated sequences")
       << "); every method of a sequence is scored on the same stamps and pairs. "
       << "ATE after SE(3) Umeyama alignment. `odom_imu` integrates the gyro only: rotation "
       << "only, as in the paper.\n\n";
    std::vector<std::string> sequences;
    for (const RunEvaluation &e : evaluations) {
        if (std::find(sequences.begin(), sequences.end(), e.sequence) == sequences.end()) {
            sequences.push_back(e.sequence);
        }
    }
    for (const std::string &seq : sequences) {
        std::vector<const RunEvaluation *> rows;
        for (const RunEvaluation &e : evaluations) {
            if (e.sequence == seq) rows.push_back(&e);
        }
        os << "## " << seq << "\n\n";
        WriteMarkdownTable(os, rows, false);
        for (const RunEvaluation *e : rows) {
            if (!e->note.empty()) os << "\n- " << e->method << ": " << e->note;
        }
        os << "\n\n";
    }
    std::vector<const RunEvaluation *> all;
    for (const RunEvaluation &e : evaluations) all.push_back(&e);
    os << "## all sequences (pairs pooled)\n\n";
    WriteMarkdownTable(os, all, true);
    os << "\nRotation error by body axis (x forward = roll, y left = pitch, z up = yaw), mean "
          "|component| of the pairs' rotation vectors, pooled:\n\n";
    WriteAxisTable(os, all);
    os << "\nFigures: fig4_angular_velocity, fig5_rpe_per_frame, fig6_rpe_per_second, "
          "fig7_trajectories, runtime_per_stage (.png and .pdf).\n";
}

}  // namespace

void WriteReport(const std::vector<RunEvaluation> &evaluations, const BenchConfig &config,
                 const std::string &out_dir) {
    const fs::path out(out_dir);
    const auto write = [&](const char *name, auto &&writer) {
        io::WriteFileAtomically((out / name).string(), writer);
    };
    write("results.csv", [&](std::ostream &os) { WriteResultsCsv(os, evaluations); });
    write("bench_runs.csv", [&](std::ostream &os) { WriteRunsCsv(os, evaluations); });
    write("rpe_pairs.csv", [&](std::ostream &os) { WriteRpePairsCsv(os, evaluations); });
    write("results.md", [&](std::ostream &os) { WriteResultsMarkdown(os, evaluations, config); });
}

}  // namespace dorado::apps
