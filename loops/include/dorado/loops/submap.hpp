#pragma once
/// @file submap.hpp
/// Keyframe submaps that can move (LIO-SAM's and kiss-slam's local maps): the written poses cut
/// into pieces of a few tens of metres (or at a large turn), each in its own frame, anchored at
/// its first pose. A scan's pose is kept relative to its anchor and the submap's static points in
/// the anchor's frame, so a correction of the anchors moves the map without touching a point.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <unordered_set>
#include <vector>

#include "dorado/core/lie.hpp"
#include "dorado/mapping/radar_mapper.hpp"
#include "dorado/mapping/voxel_key.hpp"

namespace dorado::loops {

struct SubmapConfig {
    double length_m = 40.0;   ///< a submap ends after this much path ...
    double turn_deg = 100.0;  ///< ... or this much change of heading
    double voxel_m = 0.5;     ///< its points (for recognition and verification): one per voxel
    void Validate() const;
};

/// One written pose in its submap.
struct SubmapScan {
    int64_t stamp_ns = 0;
    Eigen::Isometry3d T_anchor_base = Eigen::Isometry3d::Identity();
    double path_m = 0.0;  ///< path length of the drive up to this scan
};

/// The motion from one anchor to the next, as the mapper wrote it.
struct AnchorMotion {
    Eigen::Isometry3d T_anchor_next = Eigen::Isometry3d::Identity();
    /// Its covariance: the right perturbation of the next anchor (the written covariances
    /// composed along the scans between them).
    Matrix6d covariance = Matrix6d::Zero();
};

struct Submap {
    int id = 0;
    /// The anchor (its first scan's pose) in the mapper's world, uncorrected.
    Eigen::Isometry3d T_world_anchor = Eigen::Isometry3d::Identity();
    std::vector<SubmapScan> scans;
    /// The static points its scans added to the map, anchor frame, one per voxel_m voxel.
    Eigen::Matrix3Xf points_anchor;
    /// The motion to the next submap's anchor (set when the next submap starts).
    std::optional<AnchorMotion> to_next;
    [[nodiscard]] double path_start_m() const { return scans.front().path_m; }
    [[nodiscard]] double path_end_m() const { return scans.back().path_m; }
};

/// The covariance of T_ac = T_ab T_bc from those of T_ab (cov_ab) and T_bc (cov_bc), independent,
/// each the right perturbation of its later pose: xi_ac = Ad(T_bc^-1) xi_ab + xi_bc.
[[nodiscard]] Matrix6d ComposeCovariance(const Matrix6d &cov_ab, const Eigen::Isometry3d &T_bc,
                                         const Matrix6d &cov_bc);

/// Cuts the written poses into submaps.
class SubmapBuilder {
  public:
    explicit SubmapBuilder(const SubmapConfig &config);

    /// Adds a written pose (and its map points) to the open submap. When the pose starts a new
    /// submap, returns the one it closed (with to_next set); the pose opens the next one.
    std::optional<Submap> Add(const mapping::WrittenPose &pose);
    /// The end of the drive: the open submap, if any (without to_next).
    std::optional<Submap> Finish();

    /// The id the next Add's pose goes to when it does not start a submap (the open one's).
    [[nodiscard]] int open_id() const { return open_ ? open_->id : next_id_; }
    /// The open submap (its scans so far; its points are gathered apart until it closes).
    [[nodiscard]] const std::optional<Submap> &open() const { return open_; }

  private:
    bool StartsNewSubmap(const Eigen::Isometry3d &T_world_base, double path_m) const;
    void AddPoints(const Eigen::Matrix3Xd &points_world);

    SubmapConfig config_;
    std::optional<Submap> open_;
    std::unordered_set<mapping::VoxelKey, mapping::VoxelKeyHash> open_voxels_;
    std::vector<Eigen::Vector3f> open_points_;
    Matrix6d covariance_anchor_last_ = Matrix6d::Zero();  // of T_anchor_last
    Eigen::Isometry3d T_world_last_ = Eigen::Isometry3d::Identity();
    double path_m_ = 0.0;
    int next_id_ = 0;
    bool started_ = false;
};

}  // namespace dorado::loops
