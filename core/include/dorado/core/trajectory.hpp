#pragma once
/// @file trajectory.hpp
/// A stamped SE(3) trajectory of one body in one world frame, with interpolation at any time.

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dorado {

/// Pose of a body in the world at a time: x_world = T_world_body * x_body.
struct StampedPose {
    int64_t stamp_ns = 0;
    Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
};

/// Poses with strictly increasing stamps.
class Trajectory {
  public:
    Trajectory() = default;
    /// Takes poses in any order; sorts them. Throws std::invalid_argument on a repeated stamp.
    explicit Trajectory(std::vector<StampedPose> poses);

    /// Appends a pose; throws std::invalid_argument unless stamp_ns is after the last one.
    void Append(int64_t stamp_ns, const Eigen::Isometry3d &T_world_body);

    /// Pose at t by slerp + linear interpolation between the neighbouring poses. Empty when t is
    /// outside [front, back] or when the neighbours are more than max_gap_ns apart.
    [[nodiscard]] std::optional<Eigen::Isometry3d> Interpolate(
        int64_t stamp_ns, int64_t max_gap_ns = INT64_MAX) const;

    [[nodiscard]] const std::vector<StampedPose> &poses() const { return poses_; }
    [[nodiscard]] std::size_t size() const { return poses_.size(); }
    [[nodiscard]] bool empty() const { return poses_.empty(); }
    [[nodiscard]] const StampedPose &operator[](std::size_t i) const { return poses_[i]; }

    /// Length of the path through the positions [m].
    [[nodiscard]] double PathLength() const;

  private:
    std::vector<StampedPose> poses_;
};

}  // namespace dorado
