#pragma once
/// @file association.hpp
/// Pairing an estimated trajectory with its reference (ground truth) by time stamp.

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "dorado/core/trajectory.hpp"

namespace dorado::eval {

/// How the reference pose for an estimated stamp is found.
enum class AssociationMethod {
    /// The reference pose at the estimated stamp, interpolated (slerp + linear) between the two
    /// neighbouring reference poses; used when the reference runs at another rate (lidar vs radar).
    kInterpolate,
    /// evo's `associate_trajectories`: for each pose of the shorter trajectory, the pose of the
    /// longer one with the nearest stamp (first of ties), if no further than max_time_diff_ns.
    /// As evo, a pose of the longer trajectory may be paired with several of the shorter one.
    kNearest,
};

/// "interpolate" | "nearest".
[[nodiscard]] const char *ToString(AssociationMethod method);
/// The inverse of ToString; throws std::invalid_argument otherwise.
[[nodiscard]] AssociationMethod ParseAssociationMethod(const std::string &name);

struct AssociationConfig {
    AssociationMethod method = AssociationMethod::kInterpolate;
    /// kInterpolate: the two reference poses around the stamp may be at most this far apart [ns].
    int64_t max_gap_ns = 500'000'000;
    /// kNearest: largest |t_est - t_ref| accepted [ns]; evo's default --t_max_diff is 0.01 s.
    int64_t max_time_diff_ns = 10'000'000;
    /// kNearest: added to the estimated stamps before matching (evo's --t_offset) [ns].
    int64_t t_offset_ns = 0;
};

/// Reference and estimated poses at common stamps, in increasing time.
struct AssociatedPoses {
    std::vector<int64_t> stamps_ns;  ///< the estimated trajectory's stamps (as written, no offset)
    std::vector<Eigen::Isometry3d> T_world_ref;  ///< reference pose at stamps_ns[k]
    std::vector<Eigen::Isometry3d> T_world_est;  ///< estimated pose at stamps_ns[k]
    /// Estimated stamps that found no reference pose (outside the reference, in a gap, or too far).
    std::vector<int64_t> unmatched_est_stamps_ns;

    [[nodiscard]] std::size_t size() const { return stamps_ns.size(); }
};

/// Pairs every estimated pose with a reference pose. Never throws on an empty result: the caller
/// decides whether zero matches is an error (it usually is, and should name the files).
[[nodiscard]] AssociatedPoses Associate(const Trajectory &reference, const Trajectory &estimate,
                                        const AssociationConfig &config = {});

/// Keeps only the associations whose stamp is in `stamps_ns` (sorted): used to score every method
/// of a benchmark on the same stamps when some method skipped a scan.
[[nodiscard]] AssociatedPoses KeepStamps(const AssociatedPoses &poses,
                                         const std::vector<int64_t> &stamps_ns);

}  // namespace dorado::eval
