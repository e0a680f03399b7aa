#pragma once
/// @file output_folder.hpp
/// An `--out` folder that holds an earlier run: the files dorado's commands write there
/// (docs/outputs.md) are removed before a run writes its own, so that no earlier run's file (a
/// multi-radar run's mounts.yaml, an odometry run's velocities.csv) sits beside this run's
/// outputs as if it were one of them. Files dorado does not write are never touched.

#include <string>
#include <vector>

namespace dorado::apps {

/// Which command's outputs a folder is prepared for.
enum class OutputKind {
    kRun,    ///< `dorado odometry`, `map`, `twist`: one run's files
    kBench,  ///< `dorado bench`'s report (results, plots); its runs/ and data/ stay to resume
};

/// The names (relative to the folder) that an earlier run of that kind may have left; for kRun
/// those of odometry, map and twist alike, since any of them may have written the folder.
[[nodiscard]] std::vector<std::string> KnownOutputs(OutputKind kind);

/// Removes every known output found in @p out_dir (and masks/ if then empty); returns the names
/// removed, in KnownOutputs' order, with "masks/" for the mask files. Throws std::runtime_error
/// naming the file that cannot be removed.
std::vector<std::string> RemoveEarlierOutputs(const std::string &out_dir, OutputKind kind);

/// Creates @p out_dir if needed and removes an earlier run's outputs from it, printing one line
/// to stderr that names what was removed (nothing when the folder held none).
void PrepareOutputFolder(const std::string &out_dir, OutputKind kind = OutputKind::kRun);

}  // namespace dorado::apps
