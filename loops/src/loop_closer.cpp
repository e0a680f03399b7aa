// The loop closer's bookkeeping: submaps, graph nodes and corrections (loop_closer.hpp). The
// search for a submap's loops is in loop_search.cpp.
#include "dorado/loops/loop_closer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <string>
#include "dorado/core/require.hpp"

namespace dorado::loops {

void LoopClosureConfig::Validate() const {
    submap.Validate();
    place.Validate();
    verification.Validate();
    graph.Validate();
    auto non_negative = [](double v, const char *key) {
        Require(v >= 0.0 && std::isfinite(v), std::string("loop_closure.") + key, "must be >= 0");
    };
    non_negative(min_loop_path_m, "min_loop_path_m");
    non_negative(place_radius_m, "place_radius_m");
    non_negative(gate_sigmas, "gate_sigmas");
    non_negative(max_consistency_chi2, "max_consistency_chi2");
    Require(max_verifications >= 1, "loop_closure.max_verifications", "must be >= 1");
    Require(injected_false_fraction >= 0.0 && injected_false_fraction <= 1.0,
            "--inject-false-loops", "must be in [0, 1]");
}

std::string VerdictText(const LoopCandidate &candidate) {
    switch (candidate.verdict) {
        case CandidateVerdict::kAccepted:
            return "accepted";
        case CandidateVerdict::kNoPlaceMatch:
            return "no place match";
        case CandidateVerdict::kNotVerified:
            return "over the verification budget";
        case CandidateVerdict::kRegistration:
            return std::string("registration: ") +
                   (candidate.verification ? ToString(candidate.verification->failure) : "?");
        case CandidateVerdict::kInconsistent:
            return "inconsistent with odometry";
        case CandidateVerdict::kSwitchedOff:
            return "switched off by the graph";
        case CandidateVerdict::kInjected:
            return "injected false loop";
    }
    return "?";
}

LoopCloser::LoopCloser(const LoopClosureConfig &config) : config_(config), builder_(config.submap) {
    config_.Validate();
}

void LoopCloser::OpenNode(const Eigen::Isometry3d &T_world_anchor) {
    // A new node starts where its predecessor's correction puts it.
    const int previous = graph_.nodes() - 1;
    const Eigen::Isometry3d correction =
        previous >= 0 ? Correction(previous) : Eigen::Isometry3d::Identity();
    graph_.AddNode(correction * T_world_anchor);
    T_world_anchor_written_.push_back(T_world_anchor);
}

LoopStep LoopCloser::Add(const mapping::WrittenPose &pose) {
    std::optional<Submap> closed = builder_.Add(pose);
    if (graph_.nodes() == 0) OpenNode(pose.T_world_base);
    if (!closed) return {};
    OpenNode(pose.T_world_base);
    // The odometry edge to the new anchor. A zero covariance (a drive's first scans) gets a
    // tiny floor so that the information exists.
    RelativePoseEdge edge;
    edge.from = closed->id;
    edge.to = closed->id + 1;
    edge.T_from_to = closed->to_next->T_anchor_next;
    const Matrix6d covariance = closed->to_next->covariance + Matrix6d::Identity() * 1e-10;
    edge.information = covariance.inverse();
    edge.information = 0.5 * (edge.information + edge.information.transpose()).eval();
    edge.kind = EdgeKind::kOdometry;
    graph_.AddEdge(edge);
    return Close(std::move(*closed));
}

LoopStep LoopCloser::Finish() {
    std::optional<Submap> last = builder_.Finish();
    if (!last) return {};
    return Close(std::move(*last));
}

LoopStep LoopCloser::Close(Submap submap) {
    LoopStep step;
    step.submap_closed = true;
    const auto start = std::chrono::steady_clock::now();
    Place place;
    place.descriptor = DescribePlace(submap.points_anchor, config_.place);
    place.centre_anchor = submap.scans[submap.scans.size() / 2].T_anchor_base.translation();
    place.submap = std::move(submap);
    submaps_.push_back(std::move(place));
    step.describe_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const int query = static_cast<int>(submaps_.size()) - 1;
    FindLoops(query, step);
    if (config_.injected_false_fraction > 0.0) InjectFalseLoop(query, step);
    if (step.accepted > 0) {
        step.solution = graph_.Optimize(config_.graph);
        for (LoopCandidate &candidate : candidates_) {
            if (candidate.edge < 0) continue;
            candidate.switch_value = graph_.switch_value(candidate.edge);
            if (candidate.verdict == CandidateVerdict::kAccepted && candidate.switch_value < 0.5)
                candidate.verdict = CandidateVerdict::kSwitchedOff;
            else if (candidate.verdict == CandidateVerdict::kSwitchedOff &&
                     candidate.switch_value >= 0.5)
                candidate.verdict = CandidateVerdict::kAccepted;
        }
    }
    return step;
}

Eigen::Isometry3d LoopCloser::Correction(int node) const {
    return graph_.T_world_node(node) * T_world_anchor_written_[node].inverse();
}

const Eigen::Isometry3d &LoopCloser::T_world_anchor_written(int submap) const {
    return T_world_anchor_written_.at(submap);
}

std::vector<Eigen::Isometry3d> LoopCloser::Corrections() const {
    std::vector<Eigen::Isometry3d> corrections;
    auto add = [&](const Submap &submap) {
        const int node = submap.id;
        const Eigen::Isometry3d here = Correction(node);
        const bool has_next = node + 1 < graph_.nodes();
        const Eigen::Isometry3d next = has_next ? Correction(node + 1) : here;
        // The correction blends from this anchor's to the next one's along the submap's path.
        const double start_m = submap.path_start_m();
        double length_m = 0.0;
        if (has_next && node + 1 < static_cast<int>(submaps_.size()))
            length_m = submaps_[node + 1].submap.path_start_m() - start_m;
        else if (has_next && builder_.open())
            length_m = builder_.open()->path_start_m() - start_m;
        for (const SubmapScan &scan : submap.scans) {
            const double alpha =
                length_m > 1e-6 ? std::clamp((scan.path_m - start_m) / length_m, 0.0, 1.0) : 0.0;
            corrections.push_back(InterpolatePose(here, next, alpha));
        }
    };
    for (const Place &place : submaps_) add(place.submap);
    if (builder_.open()) add(*builder_.open());
    return corrections;
}

Trajectory LoopCloser::CorrectedTrajectory() const {
    const std::vector<Eigen::Isometry3d> corrections = Corrections();
    Trajectory trajectory;
    std::size_t i = 0;
    auto add = [&](const Submap &submap) {
        for (const SubmapScan &scan : submap.scans)
            trajectory.Append(scan.stamp_ns,
                              corrections[i++] * submap.T_world_anchor * scan.T_anchor_base);
    };
    for (const Place &place : submaps_) add(place.submap);
    if (builder_.open()) add(*builder_.open());
    return trajectory;
}

Eigen::Isometry3d LoopCloser::LatestCorrection() const {
    return graph_.nodes() > 0 ? Correction(graph_.nodes() - 1) : Eigen::Isometry3d::Identity();
}

int LoopCloser::loops_accepted() const {
    int accepted = 0;
    for (const LoopCandidate &candidate : candidates_)
        if (candidate.verdict == CandidateVerdict::kAccepted) ++accepted;
    return accepted;
}

std::size_t LoopCloser::submap_bytes() const {
    std::size_t bytes = 0;
    for (const Place &place : submaps_)
        bytes += sizeof(Place) + place.submap.points_anchor.size() * sizeof(float) +
                 place.submap.scans.capacity() * sizeof(SubmapScan) +
                 place.descriptor.descriptors.capacity() +
                 place.descriptor.keypoints_anchor.capacity() * sizeof(Eigen::Vector2f);
    return bytes;
}

}  // namespace dorado::loops
