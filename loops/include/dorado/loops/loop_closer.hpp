#pragma once
/// @file loop_closer.hpp
/// Loop closure on the mapper's written poses, off the per-scan path: the poses are cut into
/// submaps (submap.hpp); when a submap is complete, the older submaps whose places the drift
/// ellipse (the odometry chain's covariance between the two) allows to overlap it are its
/// candidates; each is compared by its bird's-eye descriptor (place_recognition.hpp), the best
/// are verified by registration (loop_verification.hpp) and checked against the odometry chain
/// (Mahalanobis distance under the chain's and the registration's covariances); an accepted loop
/// enters the anchors' pose graph (pose_graph.hpp) and the graph is solved. The corrected poses are
/// the written ones moved by their anchors' corrections (blended along each submap's path).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "dorado/core/trajectory.hpp"
#include "dorado/loops/loop_verification.hpp"
#include "dorado/loops/place_recognition.hpp"
#include "dorado/loops/pose_graph.hpp"
#include "dorado/loops/submap.hpp"
#include "dorado/mapping/radar_mapper.hpp"

namespace dorado::loops {

/// Every default is explained in configs/mapper.yaml (loop_closure:).
struct LoopClosureConfig {
    bool enabled = true;
    SubmapConfig submap;
    PlaceConfig place;
    VerificationConfig verification;
    PoseGraphConfig graph;
    double min_loop_path_m = 150.0;  ///< path between two submaps for a loop between them
    double place_radius_m = 25.0;    ///< submap centres this close (in truth) share a place
    double gate_sigmas = 3.0;   ///< the drift ellipse: this many sigmas of the chain's position
    int max_verifications = 3;  ///< descriptor matches verified per submap, most inliers first
    /// Largest squared Mahalanobis distance between the loop's relative pose and the odometry
    /// chain's (6 dof; 22.5 is chi2's 99.9 % point).
    double max_consistency_chi2 = 22.5;
    /// Robustness test only (`dorado map --inject-false-loops`): this fraction of the submaps gets
    /// a false loop edge to a place it is not near, straight into the graph (no verification).
    double injected_false_fraction = 0.0;
    void Validate() const;
};

/// What became of a loop candidate, in the order the steps run.
enum class CandidateVerdict {
    kAccepted,      ///< "accepted": in the graph, its switch on
    kNoPlaceMatch,  ///< "no place match": the descriptors do not match
    kNotVerified,   ///< "over the verification budget": a better match was verified instead
    kRegistration,  ///< the registration failed (Verification::failure says how)
    kInconsistent,  ///< "inconsistent with odometry": beyond max_consistency_chi2
    kSwitchedOff,   ///< "switched off by the graph": its switch went below 0.5
    kInjected,      ///< "injected false loop" (robustness test)
};

struct LoopCandidate {
    int query_submap = 0;                                ///< the new submap
    int candidate_submap = 0;                            ///< the older one
    int64_t query_stamp_ns = 0, candidate_stamp_ns = 0;  ///< their anchors'
    double path_between_m = 0.0;
    double distance_m = 0.0;  ///< between their centres, as estimated when the candidate was made
    double gate_m = 0.0;      ///< place_radius_m + gate_sigmas * the chain's sigma
    PlaceMatch place;
    std::optional<Verification> verification;
    double consistency_chi2 = 0.0;
    CandidateVerdict verdict = CandidateVerdict::kNoPlaceMatch;
    double switch_value = 0.0;  ///< after the last graph solve (accepted and injected ones)
    int edge = -1;              ///< its edge in the graph (accepted and injected ones)
    double detect_ms = 0.0;     ///< its descriptor comparison
    double verify_ms = 0.0;     ///< its registration
};

/// What one Add or Finish did.
struct LoopStep {
    bool submap_closed = false;
    int candidates = 0;  ///< new candidates (appended to candidates())
    int accepted = 0;
    std::optional<PoseGraphSolution> solution;  ///< when the graph was solved
    double describe_ms = 0.0;                   ///< the closed submap's descriptor
    double detect_ms = 0.0;                     ///< gating and descriptor comparisons
    double verify_ms = 0.0;                     ///< registrations and the consistency checks
};

class LoopCloser {
  public:
    explicit LoopCloser(const LoopClosureConfig &config);

    /// Adds the next written pose; when it completes a submap, looks for that submap's loops.
    LoopStep Add(const mapping::WrittenPose &pose);
    /// The end of the drive: the last submap is complete.
    LoopStep Finish();

    /// The correction of every written pose so far, in order: T_world_base corrected =
    /// corrections[i] * T_world_base written (world frame on both sides).
    [[nodiscard]] std::vector<Eigen::Isometry3d> Corrections() const;
    /// The corrected trajectory (every written pose, corrected).
    [[nodiscard]] Trajectory CorrectedTrajectory() const;
    /// The newest pose's correction: the live node's map -> odom.
    [[nodiscard]] Eigen::Isometry3d LatestCorrection() const;

    [[nodiscard]] const std::vector<LoopCandidate> &candidates() const { return candidates_; }
    [[nodiscard]] const PoseGraph &graph() const { return graph_; }
    [[nodiscard]] int submaps() const { return static_cast<int>(submaps_.size()); }
    [[nodiscard]] int loops_accepted() const;
    /// Bytes held by the submaps' points, scans and descriptors (memory per km).
    [[nodiscard]] std::size_t submap_bytes() const;
    /// The anchor of a submap in the mapper's world (uncorrected) and corrected.
    [[nodiscard]] const Eigen::Isometry3d &T_world_anchor_written(int submap) const;

  private:
    struct Place {  // a complete submap, kept compactly
        Submap submap;
        PlaceDescriptor descriptor;
        Eigen::Vector3d centre_anchor = Eigen::Vector3d::Zero();
    };
    void OpenNode(const Eigen::Isometry3d &T_world_anchor);
    LoopStep Close(Submap submap);
    void FindLoops(int query, LoopStep &step);
    void InjectFalseLoop(int query, LoopStep &step);
    Eigen::Isometry3d Correction(int node) const;

    LoopClosureConfig config_;
    SubmapBuilder builder_;
    std::vector<Place> submaps_;                             // complete, in order (index = id)
    std::vector<Eigen::Isometry3d> T_world_anchor_written_;  // every node's, open one included
    PoseGraph graph_;
    std::vector<LoopCandidate> candidates_;
    std::mt19937 injection_random_{7};
};

/// "accepted", "no place match", "over the verification budget", "registration: <failure>",
/// "inconsistent with odometry", "switched off by the graph", "injected false loop".
[[nodiscard]] std::string VerdictText(const LoopCandidate &candidate);

}  // namespace dorado::loops
