#include "dorado/eval/association.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>

namespace dorado::eval {

namespace {

// Index of the stamp in `stamps` nearest to t; on a tie the earlier one (numpy's argmin).
std::size_t NearestIndex(const std::vector<StampedPose> &poses, int64_t t) {
    const auto after =
        std::lower_bound(poses.begin(), poses.end(), t,
                         [](const StampedPose &p, int64_t stamp) { return p.stamp_ns < stamp; });
    if (after == poses.begin()) return 0;
    if (after == poses.end()) return poses.size() - 1;
    const auto before = std::prev(after);
    const std::size_t i_after = static_cast<std::size_t>(after - poses.begin());
    return (t - before->stamp_ns) <= (after->stamp_ns - t) ? i_after - 1 : i_after;
}

AssociatedPoses AssociateInterpolated(const Trajectory &reference, const Trajectory &estimate,
                                      int64_t max_gap_ns) {
    AssociatedPoses out;
    for (const StampedPose &est : estimate.poses()) {
        const auto T_world_ref = reference.Interpolate(est.stamp_ns, max_gap_ns);
        if (!T_world_ref) {
            out.unmatched_est_stamps_ns.push_back(est.stamp_ns);
            continue;
        }
        out.stamps_ns.push_back(est.stamp_ns);
        out.T_world_ref.push_back(*T_world_ref);
        out.T_world_est.push_back(est.T_world_body);
    }
    return out;
}

// evo's sync.associate_trajectories(ref, est, max_diff, offset_2): the shorter trajectory
// drives the matching; est stamps are shifted by the offset; pairs are in the shorter's order.
AssociatedPoses AssociateNearest(const Trajectory &reference, const Trajectory &estimate,
                                 const AssociationConfig &config) {
    AssociatedPoses out;
    if (reference.empty() || estimate.empty()) {
        for (const auto &p : estimate.poses()) out.unmatched_est_stamps_ns.push_back(p.stamp_ns);
        return out;
    }
    const bool est_longer = estimate.size() > reference.size();
    std::vector<bool> est_matched(estimate.size(), false);
    const auto add = [&](std::size_t i_est, std::size_t i_ref) {
        est_matched[i_est] = true;
        out.stamps_ns.push_back(estimate[i_est].stamp_ns);
        out.T_world_ref.push_back(reference[i_ref].T_world_body);
        out.T_world_est.push_back(estimate[i_est].T_world_body);
    };
    if (est_longer) {
        // Nearest shifted estimate stamp for each reference stamp: t_est + offset ~ t_ref.
        for (std::size_t r = 0; r < reference.size(); ++r) {
            const int64_t t = reference[r].stamp_ns - config.t_offset_ns;
            const std::size_t e = NearestIndex(estimate.poses(), t);
            if (std::llabs(estimate[e].stamp_ns - t) <= config.max_time_diff_ns) add(e, r);
        }
    } else {
        for (std::size_t e = 0; e < estimate.size(); ++e) {
            const int64_t t = estimate[e].stamp_ns + config.t_offset_ns;
            const std::size_t r = NearestIndex(reference.poses(), t);
            if (std::llabs(reference[r].stamp_ns - t) <= config.max_time_diff_ns) add(e, r);
        }
    }
    for (std::size_t i = 0; i < estimate.size(); ++i) {
        if (!est_matched[i]) out.unmatched_est_stamps_ns.push_back(estimate[i].stamp_ns);
    }
    return out;
}

}  // namespace

const char *ToString(AssociationMethod method) {
    return method == AssociationMethod::kNearest ? "nearest" : "interpolate";
}

AssociationMethod ParseAssociationMethod(const std::string &name) {
    if (name == "interpolate") return AssociationMethod::kInterpolate;
    if (name == "nearest") return AssociationMethod::kNearest;
    throw std::invalid_argument("must be interpolate or nearest, got '" + name + "'");
}

AssociatedPoses Associate(const Trajectory &reference, const Trajectory &estimate,
                          const AssociationConfig &config) {
    if (config.method == AssociationMethod::kNearest) {
        return AssociateNearest(reference, estimate, config);
    }
    return AssociateInterpolated(reference, estimate, config.max_gap_ns);
}

AssociatedPoses KeepStamps(const AssociatedPoses &poses, const std::vector<int64_t> &stamps_ns) {
    AssociatedPoses out;
    out.unmatched_est_stamps_ns = poses.unmatched_est_stamps_ns;
    for (std::size_t k = 0; k < poses.size(); ++k) {
        if (!std::binary_search(stamps_ns.begin(), stamps_ns.end(), poses.stamps_ns[k])) continue;
        out.stamps_ns.push_back(poses.stamps_ns[k]);
        out.T_world_ref.push_back(poses.T_world_ref[k]);
        out.T_world_est.push_back(poses.T_world_est[k]);
    }
    return out;
}

}  // namespace dorado::eval
