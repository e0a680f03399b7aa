#include "output_folder.hpp"

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "dorado/io/atomic_file.hpp"

namespace dorado::apps {

namespace fs = std::filesystem;

namespace {

/// masks/NNNNNN.txt (WriteMaskFile): six digits and ".txt".
bool IsMaskFile(const fs::directory_entry &entry) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_regular_file() || name.size() != 10 || name.substr(6) != ".txt") return false;
    for (std::size_t i = 0; i < 6; ++i) {
        if (!std::isdigit(static_cast<unsigned char>(name[i]))) return false;
    }
    return true;
}

void Remove(const fs::path &path) {
    std::error_code ec;
    fs::remove(path, ec);
    if (ec)
        throw std::runtime_error(path.string() +
                                 ": cannot remove an earlier run's output: " + ec.message());
}

/// Removes the mask files under @p masks and the folder if nothing else is in it.
bool RemoveMasks(const fs::path &masks) {
    std::error_code ec;
    if (!fs::is_directory(masks, ec)) return false;
    bool removed = false;
    for (const auto &entry : fs::directory_iterator(masks)) {
        if (!IsMaskFile(entry)) continue;
        Remove(entry.path());
        removed = true;
    }
    if (fs::is_empty(masks, ec)) Remove(masks);
    return removed;
}

}  // namespace

std::vector<std::string> KnownOutputs(OutputKind kind) {
    switch (kind) {
        case OutputKind::kRun:
            return {"trajectory.tum",
                    "summary.json",
                    "velocities.csv",
                    "scans.csv",
                    "covariance.csv",
                    "map.pcd",
                    "map.ply",
                    "map.png",
                    "mounts.yaml",
                    "twist.csv",
                    "loops.csv",
                    "graph.g2o",
                    "trajectory_uncorrected.tum"};
        case OutputKind::kBench: {
            std::vector<std::string> names{"results.md", "results.csv", "bench_runs.csv",
                                           "rpe_pairs.csv"};
            // scripts/plot_benchmark.py's figures, each as PNG and PDF.
            for (const char *figure :
                 {"fig4_angular_velocity", "fig5_rpe_per_frame", "fig6_rpe_per_second",
                  "fig7_trajectories", "runtime_per_stage"}) {
                names.push_back(std::string("plots/") + figure + ".png");
                names.push_back(std::string("plots/") + figure + ".pdf");
            }
            return names;
        }
    }
    return {};
}

std::vector<std::string> RemoveEarlierOutputs(const std::string &out_dir, OutputKind kind) {
    std::vector<std::string> removed;
    for (const std::string &name : KnownOutputs(kind)) {
        const fs::path path = fs::path(out_dir) / name;
        std::error_code ec;
        if (!fs::is_regular_file(path, ec)) continue;
        Remove(path);
        removed.push_back(name);
    }
    if (kind == OutputKind::kRun && RemoveMasks(fs::path(out_dir) / "masks"))
        removed.push_back("masks/");
    return removed;
}

void PrepareOutputFolder(const std::string &out_dir, OutputKind kind) {
    io::MakeDirectories(out_dir);
    const std::vector<std::string> removed = RemoveEarlierOutputs(out_dir, kind);
    if (removed.empty()) return;
    std::string list;
    for (const auto &name : removed) list += (list.empty() ? "" : ", ") + name;
    std::fprintf(stderr, "dorado: %s held an earlier run's outputs, removed: %s\n", out_dir.c_str(),
                 list.c_str());
}

}  // namespace dorado::apps
