#pragma once
/// @file multi_radar_map.hpp
/// `dorado map` on a description with a `radars:` list: every radar into one map
/// (frontend::MultiRadarFrontEnd), the same outputs as one radar's map plus a per-radar record.

#include <nlohmann/json.hpp>
#include <string>

#include "dorado/frontend/radar_front_end.hpp"
#include "dorado/io/dataset_config.hpp"
#include "dorado/loops/loop_closer.hpp"
#include "dorado/odometry/planar_twist_filter.hpp"

namespace dorado::apps {

/// Maps every radar of dataset.radars into out_dir (trajectory.tum at the first radar's stamps,
/// map.*, scans.csv one row per sweep, covariance.csv, summary.json with "radars"). Throws
/// io::ConfigError / io::DatasetError naming the file; StoppedEarly after writing what was done,
/// or when the results are implausible and not @p accept_implausible (plausibility.hpp).
void RunMultiRadarMap(const io::DatasetConfig &dataset, const frontend::FrontEndConfig &config,
                      const loops::LoopClosureConfig &loop_config,
                      const odometry::PlanarTwistFilterConfig &twist_filter,
                      const std::string &out_dir, bool accept_implausible);

/// Radar k's record for summary.json's "radars": its mount yaw offset from the published one and
/// its 1-sigma [deg], and whether it was estimated.
[[nodiscard]] nlohmann::json MountRecord(const odometry::PlanarTwistFilter &filter, std::size_t k);
/// Writes out_dir/mounts.yaml: the dataset's `radars:` list with each mount as calibrated (the
/// published one turned by its estimated yaw offset), to paste into the next run's description.
void WriteCalibratedMounts(const std::string &out_dir, const io::DatasetConfig &dataset,
                           const odometry::PlanarTwistFilter &filter);

}  // namespace dorado::apps
