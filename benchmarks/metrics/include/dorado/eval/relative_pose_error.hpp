#pragma once
/// @file relative_pose_error.hpp
/// Relative pose error (RPE) of the TUM RGB-D benchmark, with evo's definitions: for a pair (i, j)
/// of associated poses, reference Q and estimate P,
///   E_ij = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j),
/// scored by |translation(E_ij)| [m] and the rotation angle of E_ij [deg]. Pairs are consecutive
/// (not all pairs) and chosen on the REFERENCE (stamps, path length), so that every method
/// evaluated on the same stamps is scored on the same pairs.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "dorado/eval/association.hpp"
#include "dorado/eval/statistics.hpp"

namespace dorado::eval {

enum class DeltaUnit {
    kFrames,   ///< j = i + delta (evo's --delta_unit f)
    kSeconds,  ///< t_j - t_i = delta within a relative tolerance (the paper's "RPE per second")
    kMeters,   ///< path length travelled by the reference from i to j >= delta
};

/// Parses "frames"/"f", "seconds"/"s", "meters"/"m"; throws std::invalid_argument otherwise.
[[nodiscard]] DeltaUnit ParseDeltaUnit(const std::string &text);
[[nodiscard]] std::string ToString(DeltaUnit unit);

struct PairSelection {
    double delta = 1.0;
    DeltaUnit unit = DeltaUnit::kFrames;
    /// kSeconds: a pair is kept when |t_j - t_i - delta| <= relative_tolerance * delta
    /// (evo's --delta_tol default 0.1), so that a gap in the data does not make a longer pair.
    double relative_tolerance = 0.1;
};

struct PosePair {
    std::size_t i = 0;
    std::size_t j = 0;
};

/// Consecutive pairs over the associated poses, chosen on the reference:
/// - frames: (0, d), (d, 2d), ... exactly as evo's filter_pairs_by_index;
/// - seconds: from i, the j whose stamp is nearest to t_i + delta, kept within the tolerance, then
///   i = j; when no j is in tolerance (a gap), i advances by one;
/// - meters: from i, the first j at which the reference path length since i reaches delta, then
///   i = j (evo's path filter starts its first pair only after delta; this one starts at 0).
/// Throws std::invalid_argument for a delta that is not positive (or not an integer in frames).
[[nodiscard]] std::vector<PosePair> SelectPairs(const AssociatedPoses &poses,
                                                const PairSelection &selection);

/// RPE of every pair, in pair order.
struct RelativeErrors {
    std::vector<PosePair> pairs;
    std::vector<int64_t> stamp_i_ns;
    std::vector<int64_t> stamp_j_ns;
    std::vector<double> translation_m;  ///< |t(E_ij)|
    std::vector<double> rotation_deg;   ///< angle(R(E_ij))
    /// |x|, |y|, |z| of the rotation vector of R(E_ij) [deg], body axes (a vehicle's base frame:
    /// x forward = roll, y left = pitch, z up = yaw). Where the rotation error lives.
    std::vector<double> roll_deg;
    std::vector<double> pitch_deg;
    std::vector<double> yaw_deg;
};

/// E_ij for one pair (exposed for tests and for callers with their own pairs).
[[nodiscard]] Eigen::Isometry3d RelativePoseError(const Eigen::Isometry3d &Q_i,
                                                  const Eigen::Isometry3d &Q_j,
                                                  const Eigen::Isometry3d &P_i,
                                                  const Eigen::Isometry3d &P_j);

[[nodiscard]] RelativeErrors ComputeRpe(const AssociatedPoses &poses,
                                        const std::vector<PosePair> &pairs);

/// SelectPairs then ComputeRpe.
[[nodiscard]] RelativeErrors ComputeRpe(const AssociatedPoses &poses,
                                        const PairSelection &selection);

}  // namespace dorado::eval
