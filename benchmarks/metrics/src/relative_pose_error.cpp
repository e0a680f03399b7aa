#include "dorado/eval/relative_pose_error.hpp"

#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/core/time.hpp"

namespace dorado::eval {

namespace {

std::vector<PosePair> PairsByFrames(std::size_t n, std::size_t delta) {
    std::vector<PosePair> pairs;
    for (std::size_t i = 0; i + delta < n; i += delta) pairs.push_back({i, i + delta});
    return pairs;
}

std::vector<PosePair> PairsBySeconds(const std::vector<int64_t> &stamps_ns, double delta_s,
                                     double tolerance) {
    std::vector<PosePair> pairs;
    const double max_error_s = tolerance * delta_s;
    std::size_t i = 0;
    while (i + 1 < stamps_ns.size()) {
        // The j > i whose t_j - t_i is nearest to delta (stamps increase, so scan forward).
        const auto elapsed_s = [&](std::size_t j) {
            return NanosToSeconds(stamps_ns[j] - stamps_ns[i]);
        };
        std::size_t j = i + 1;
        while (j + 1 < stamps_ns.size() &&
               std::abs(elapsed_s(j + 1) - delta_s) <= std::abs(elapsed_s(j) - delta_s)) {
            ++j;
        }
        if (std::abs(elapsed_s(j) - delta_s) <= max_error_s) {
            pairs.push_back({i, j});
            i = j;
        } else if (j + 1 == stamps_ns.size() && elapsed_s(j) < delta_s) {
            break;  // the end of the data: no later pose is far enough from i
        } else {
            ++i;  // a gap near t_i + delta: try from the next pose
        }
    }
    return pairs;
}

std::vector<PosePair> PairsByMeters(const std::vector<Eigen::Isometry3d> &T_world_ref,
                                    double delta_m) {
    std::vector<PosePair> pairs;
    std::size_t i = 0;
    double path_m = 0.0;
    for (std::size_t j = 1; j < T_world_ref.size(); ++j) {
        path_m += (T_world_ref[j].translation() - T_world_ref[j - 1].translation()).norm();
        if (path_m >= delta_m) {
            pairs.push_back({i, j});
            i = j;
            path_m = 0.0;
        }
    }
    return pairs;
}

}  // namespace

DeltaUnit ParseDeltaUnit(const std::string &text) {
    if (text == "frames" || text == "f") return DeltaUnit::kFrames;
    if (text == "seconds" || text == "s") return DeltaUnit::kSeconds;
    if (text == "meters" || text == "m") return DeltaUnit::kMeters;
    throw std::invalid_argument("unknown delta unit '" + text +
                                "' (expected frames, seconds or meters)");
}

std::string ToString(DeltaUnit unit) {
    switch (unit) {
        case DeltaUnit::kFrames:
            return "frames";
        case DeltaUnit::kSeconds:
            return "seconds";
        case DeltaUnit::kMeters:
            return "meters";
    }
    return "?";
}

std::vector<PosePair> SelectPairs(const AssociatedPoses &poses, const PairSelection &selection) {
    if (!(selection.delta > 0.0) || !std::isfinite(selection.delta)) {
        throw std::invalid_argument("RPE delta must be a positive number, got " +
                                    std::to_string(selection.delta));
    }
    if (!(selection.relative_tolerance >= 0.0)) {
        throw std::invalid_argument("RPE relative tolerance must be >= 0");
    }
    switch (selection.unit) {
        case DeltaUnit::kFrames: {
            if (std::floor(selection.delta) != selection.delta) {
                throw std::invalid_argument("RPE delta in frames must be an integer, got " +
                                            std::to_string(selection.delta));
            }
            return PairsByFrames(poses.size(), static_cast<std::size_t>(selection.delta));
        }
        case DeltaUnit::kSeconds:
            return PairsBySeconds(poses.stamps_ns, selection.delta, selection.relative_tolerance);
        case DeltaUnit::kMeters:
            return PairsByMeters(poses.T_world_ref, selection.delta);
    }
    return {};
}

Eigen::Isometry3d RelativePoseError(const Eigen::Isometry3d &Q_i, const Eigen::Isometry3d &Q_j,
                                    const Eigen::Isometry3d &P_i, const Eigen::Isometry3d &P_j) {
    // Motion from i to j in the body frame at i, according to the reference and to the estimate;
    // E is the estimate's motion seen from the reference's (identity when they agree).
    const Eigen::Isometry3d Q_ij = Q_i.inverse() * Q_j;
    const Eigen::Isometry3d P_ij = P_i.inverse() * P_j;
    return Q_ij.inverse() * P_ij;
}

RelativeErrors ComputeRpe(const AssociatedPoses &poses, const std::vector<PosePair> &pairs) {
    RelativeErrors out;
    out.pairs = pairs;
    for (const PosePair &pair : pairs) {
        if (pair.i >= poses.size() || pair.j >= poses.size()) {
            throw std::out_of_range("RPE pair index beyond the associated poses");
        }
        const Eigen::Isometry3d E =
            RelativePoseError(poses.T_world_ref[pair.i], poses.T_world_ref[pair.j],
                              poses.T_world_est[pair.i], poses.T_world_est[pair.j]);
        out.stamp_i_ns.push_back(poses.stamps_ns[pair.i]);
        out.stamp_j_ns.push_back(poses.stamps_ns[pair.j]);
        out.translation_m.push_back(E.translation().norm());
        // Angle of the rotation vector (quaternion route), as evo's so3_log_angle: accurate near 0.
        const Eigen::Vector3d rotation_vector = RadToDeg(LogSO3(E.linear()));
        out.rotation_deg.push_back(rotation_vector.norm());
        out.roll_deg.push_back(std::abs(rotation_vector.x()));
        out.pitch_deg.push_back(std::abs(rotation_vector.y()));
        out.yaw_deg.push_back(std::abs(rotation_vector.z()));
    }
    return out;
}

RelativeErrors ComputeRpe(const AssociatedPoses &poses, const PairSelection &selection) {
    return ComputeRpe(poses, SelectPairs(poses, selection));
}

}  // namespace dorado::eval
