#pragma once
/// @file map_outputs.hpp
/// What `dorado map` writes: scans.csv (per scan: time per stage, prior, registration, local map
/// size), the map (map.pcd, map.ply, map.png: every point the mapper added to its map, where it
/// placed it), trajectory.tum, and the per-run counts for summary.json.

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <unordered_map>
#include <vector>

#include "covariance_table.hpp"
#include "dorado/frontend/radar_front_end.hpp"
#include "map_image.hpp"

namespace dorado::apps {

/// A loop closure's corrections of what was written (loop_outputs.hpp).
struct MapCorrection {
    /// Per written pose, in order: corrected = correction * as written (world frame).
    std::vector<Eigen::Isometry3d> corrections;
    std::vector<LoopEdge> loops_world;  ///< drawn on map.png
};

class MapOutputs {
  public:
    /// map_cell_m: the mapper's map.voxel_size_m (the cells it may empty).
    explicit MapOutputs(double map_cell_m = 1.0);

    /// Records one accepted scan, and the poses written with it.
    void Add(const frontend::FrontEndResult &result);
    /// Records written poses (the map's points, covariance.csv, map.png's track): Add's, and the
    /// ones the end of the drive writes (the front end's Finish).
    void AddWritten(const std::vector<mapping::WrittenPose> &written);

    /// Writes trajectory.tum, the map files, scans.csv and covariance.csv into out_dir.
    /// map.pcd holds the points in the order the mapper added them; map.png draws
    /// reference_world (the dataset's ground truth in the map's world, empty: none) too. With a
    /// correction (loop closure), `trajectory` is the corrected one, each point moves with the
    /// pose that added it and map.png marks the loops.
    void Write(const std::string &out_dir, const Trajectory &trajectory,
               const std::vector<Eigen::Vector3d> &reference_world = {},
               const MapCorrection *correction = nullptr) const;

    /// The counts and timings for summary.json: fallbacks and their reasons, prior
    /// substitutions, scans without a mask, time per scan and per stage (mean, median, p95).
    [[nodiscard]] nlohmann::json Summary() const;

    [[nodiscard]] double mean_time_ms() const;
    [[nodiscard]] int fallbacks() const { return fallbacks_; }
    /// The map as written: every point the mapper added (world frame), each moved by its written
    /// pose's correction when there are corrections.
    [[nodiscard]] Eigen::Matrix3Xd MapPoints(
        const std::vector<Eigen::Isometry3d> *corrections = nullptr) const;

  private:
    /// A map point as added (world frame, float: sub-millimetre within 100 km) and the written
    /// pose that added it (its index in the order written).
    struct MapPoint {
        Eigen::Vector3f p_world;
        uint32_t written_index;
    };
    /// The mapper's additions by map cell, less the cells it emptied (movers): its map as it was.
    std::unordered_map<mapping::VoxelKey, std::vector<MapPoint>, mapping::VoxelKeyHash>
        map_points_world_;
    uint32_t written_ = 0;  ///< written poses so far
    std::size_t map_point_count_ = 0;
    double map_cell_m_ = 1.0;
    std::vector<Eigen::Vector3d> positions_;
    std::string csv_;
    CovarianceTable covariances_;
    std::map<std::string, std::vector<double>> stage_ms_;  ///< by stage name
    static constexpr double kYoungMapS = 5.0;  ///< fallbacks in the map's first seconds, apart
    std::map<mapping::FallbackCause, int> fallback_reasons_, young_map_fallback_reasons_;
    std::map<frontend::SubstitutionCause, int> prior_substitutions_;
    std::map<odometry::PredictionUse, int> predictions_;  ///< scans by the held RANSAC's use
    int fallbacks_ = 0, unmasked_ = 0, scans_ = 0;
    long long mover_points_dropped_ = 0, map_points_dropped_ = 0;
    /// Fallbacks per kYoungMapS-long interval since the first scan (when they happen in a run).
    std::vector<int> fallbacks_by_time_;
    odometry::YawCalibrationStep yaw_calibration_;  ///< the last scan's (online s_x)
    std::map<odometry::YawCalibrationStatus, int> yaw_calibration_counts_;  ///< scans by status
    int64_t first_stamp_ns_ = -1;
    std::size_t max_local_map_points_ = 0;
};

/// {"mean", "median", "p95"} of the values (null when empty).
[[nodiscard]] nlohmann::json TimeStatistics(std::vector<double> values_ms);

/// summary.json's description of a map run: dataset, prior, mask, refinement, method and whether
/// the stream stopped early (`stopped`: empty when it did not).
[[nodiscard]] nlohmann::json MapRunSummary(const std::string &dataset_name,
                                           const frontend::FrontEndConfig &config,
                                           const std::string &stopped);

}  // namespace dorado::apps
