#pragma once
/// @file multi_radar_map.hpp
/// `dorado map` on a description with a `radars:` list: every radar into one map
/// (frontend::MultiRadarFrontEnd), the same outputs as one radar's map plus a per-radar record.

#include <string>

#include "dorado/frontend/radar_front_end.hpp"
#include "dorado/io/dataset_config.hpp"

namespace dorado::apps {

/// Maps every radar of dataset.radars into out_dir (trajectory.tum at the first radar's stamps,
/// map.*, scans.csv one row per sweep, covariance.csv, summary.json with "radars"). Throws
/// io::ConfigError / io::DatasetError naming the file; StoppedEarly after writing what was done.
void RunMultiRadarMap(const io::DatasetConfig &dataset, const frontend::FrontEndConfig &config,
                      const std::string &out_dir);

}  // namespace dorado::apps
