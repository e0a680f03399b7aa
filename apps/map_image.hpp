#pragma once
/// @file map_image.hpp
/// Bird's-eye picture of a map and a trajectory (OpenCV): map points coloured by height, the
/// trajectory coloured by time, the reference trajectory (when the dataset has one) dashed black,
/// the loop closures red, north (world +Y) up, with a scale bar and a legend.

#include <Eigen/Core>
#include <string>
#include <vector>

namespace dorado::apps {

/// A loop closure as drawn: the two places it joins (their submaps' centres, world frame).
struct LoopEdge {
    Eigen::Vector3d from_world;
    Eigen::Vector3d to_world;
};

/// Writes a PNG at `path`. reference_world: the reference trajectory in the same world (empty:
/// none); loop_edges_world: the accepted loop closures (empty: none). max_side_px bounds the larger
/// image side. Throws std::runtime_error naming the file when it cannot be written.
void WriteBirdsEyeImage(const std::string &path, const Eigen::Matrix3Xd &map_points_world,
                        const std::vector<Eigen::Vector3d> &trajectory_world,
                        const std::vector<Eigen::Vector3d> &reference_world = {},
                        const std::vector<LoopEdge> &loop_edges_world = {}, int max_side_px = 1600);

}  // namespace dorado::apps
