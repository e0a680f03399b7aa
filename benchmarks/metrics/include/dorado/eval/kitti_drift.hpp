#pragma once
/// @file kitti_drift.hpp
/// The KITTI odometry benchmark's drift (Geiger et al. 2012, devkit's evaluate_odometry): over
/// every segment of 100, 200, ..., 800 m of the REFERENCE path, starting every step_frames
/// poses, the error E = (P_i^-1 P_j)^-1 (Q_i^-1 Q_j) of the segment's end relative to its start,
/// as |t(E)| / length (translation drift) and angle(R(E)) / length (rotation drift), averaged
/// over all segments.

#include <vector>

#include "dorado/eval/association.hpp"

namespace dorado::eval {

struct DriftConfig {
    std::vector<double> lengths_m{100, 200, 300, 400, 500, 600, 700, 800};
    int step_frames = 10;  ///< segment starts every this many poses (the devkit's 10)
};

struct DriftResult {
    int segments = 0;                    ///< 0: the path is shorter than the shortest length
    double translation_percent = 0.0;    ///< mean |t(E)| / length * 100
    double rotation_deg_per_100m = 0.0;  ///< mean angle(R(E)) / length, in deg per 100 m
};

/// Throws std::invalid_argument for an empty length list, a length <= 0 or step_frames < 1.
[[nodiscard]] DriftResult ComputeKittiDrift(const AssociatedPoses &poses,
                                            const DriftConfig &config = {});

}  // namespace dorado::eval
