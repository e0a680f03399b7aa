// A complete submap's loops: gate, describe, verify, check against the odometry (loop_closer.hpp).
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>

#include "dorado/loops/loop_closer.hpp"

namespace dorado::loops {
namespace {

double MillisecondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
}

// The largest standard deviation, in the plane, of a point c_b (frame b) seen from frame a through
// T_ab with covariance cov_ab: p = T_ab Exp(xi) c_b ~ T_ab c_b + R_ab (rho - Hat(c_b) phi).
double PlanarSigma(const Eigen::Isometry3d &T_ab, const Matrix6d &cov_ab,
                   const Eigen::Vector3d &c_b) {
    Eigen::Matrix<double, 3, 6> J;
    J.leftCols<3>() = T_ab.rotation();
    J.rightCols<3>() = -T_ab.rotation() * Hat(c_b);
    const Eigen::Matrix2d planar = (J * cov_ab * J.transpose()).topLeftCorner<2, 2>();
    return std::sqrt(
        std::max(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(planar).eigenvalues()(1), 0.0));
}

// The starting guess of the verification: the place match's motion in the plane, with the
// height, roll and pitch of the odometry's relative pose.
Eigen::Isometry3d GuessFromPlace(const PlaceMatch &match, const Eigen::Isometry3d &T_odometry) {
    const Eigen::Vector3d rpy = RollPitchYaw(T_odometry.rotation());
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = RotationFromRollPitchYaw({rpy.x(), rpy.y(), match.xy_yaw_candidate_query.z()});
    T.translation() << match.xy_yaw_candidate_query.x(), match.xy_yaw_candidate_query.y(),
        T_odometry.translation().z();
    return T;
}

}  // namespace

void LoopCloser::FindLoops(int query, LoopStep &step) {
    const auto gate_start = std::chrono::steady_clock::now();
    const Place &q = submaps_[query];
    const Eigen::Isometry3d &T_world_q = T_world_anchor_written_[query];
    const Eigen::Vector3d centre_q_corrected = graph_.T_world_node(query) * q.centre_anchor;
    // The odometry chain's covariance from each older anchor c to the query's, composed backwards:
    // cov(c -> query) = Compose(cov(c -> c+1), T_{c+1,query}, cov(c+1 -> query)).
    Matrix6d chain_covariance = Matrix6d::Zero();
    std::vector<LoopCandidate> found;
    std::vector<Matrix6d> found_chain_covariance;  // per candidate: cov(candidate -> query)
    for (int c = query - 1; c >= 0; --c) {
        const Submap &older = submaps_[c].submap;
        const Eigen::Isometry3d T_next_query = T_world_anchor_written_[c + 1].inverse() * T_world_q;
        chain_covariance =
            ComposeCovariance(older.to_next->covariance, T_next_query, chain_covariance);
        const double path_between = q.submap.path_start_m() - older.path_end_m();
        if (path_between < config_.min_loop_path_m) continue;
        const Eigen::Isometry3d T_c_query = T_world_anchor_written_[c].inverse() * T_world_q;
        LoopCandidate candidate;
        candidate.query_submap = query;
        candidate.candidate_submap = c;
        candidate.query_stamp_ns = q.submap.scans.front().stamp_ns;
        candidate.candidate_stamp_ns = older.scans.front().stamp_ns;
        candidate.path_between_m = path_between;
        candidate.distance_m =
            (graph_.T_world_node(c) * submaps_[c].centre_anchor - centre_q_corrected)
                .head<2>()
                .norm();
        candidate.gate_m =
            config_.place_radius_m +
            config_.gate_sigmas * PlanarSigma(T_c_query, chain_covariance, q.centre_anchor);
        if (candidate.distance_m > candidate.gate_m) continue;
        const auto detect_start = std::chrono::steady_clock::now();
        candidate.place = MatchPlaces(q.descriptor, submaps_[c].descriptor, config_.place);
        candidate.detect_ms = MillisecondsSince(detect_start);
        candidate.verdict = candidate.place.found ? CandidateVerdict::kNotVerified
                                                  : CandidateVerdict::kNoPlaceMatch;
        found.push_back(candidate);
        found_chain_covariance.push_back(chain_covariance);
    }
    step.detect_ms = MillisecondsSince(gate_start);

    // The best descriptor matches (most inliers) are verified, at most max_verifications.
    std::vector<std::size_t> order(found.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return found[a].place.inliers > found[b].place.inliers;
    });
    int verified = 0;
    for (std::size_t i : order) {
        LoopCandidate &candidate = found[i];
        if (!candidate.place.found || verified >= config_.max_verifications) continue;
        ++verified;
        const auto verify_start = std::chrono::steady_clock::now();
        const int c = candidate.candidate_submap;
        const Eigen::Isometry3d T_c_query = T_world_anchor_written_[c].inverse() * T_world_q;
        candidate.verification =
            VerifyLoop(submaps_[c].submap.points_anchor, q.submap.points_anchor,
                       GuessFromPlace(candidate.place, T_c_query), config_.verification);
        const Verification &v = *candidate.verification;
        if (!v.accepted()) {
            candidate.verdict = CandidateVerdict::kRegistration;
        } else {
            // Consistency with the odometry chain between the two places: the loop's relative
            // pose against the chain's, under both covariances.
            const Matrix6d covariance = found_chain_covariance[i] + v.information.inverse();
            const Vector6d error = LogSE3(T_c_query.inverse() * v.T_candidate_query);
            candidate.consistency_chi2 = error.dot(covariance.ldlt().solve(error));
            if (candidate.consistency_chi2 > config_.max_consistency_chi2) {
                candidate.verdict = CandidateVerdict::kInconsistent;
            } else {
                candidate.verdict = CandidateVerdict::kAccepted;
                RelativePoseEdge edge;
                edge.from = c;
                edge.to = query;
                edge.T_from_to = v.T_candidate_query;
                edge.information = v.information;
                edge.kind = EdgeKind::kLoop;
                candidate.edge = graph_.AddEdge(edge);
                ++step.accepted;
            }
        }
        candidate.verify_ms = MillisecondsSince(verify_start);
        step.verify_ms += candidate.verify_ms;
    }
    step.candidates += static_cast<int>(found.size());
    candidates_.insert(candidates_.end(), found.begin(), found.end());
}

void LoopCloser::InjectFalseLoop(int query, LoopStep &step) {
    // A false loop as a wrong place match that passed verification would make one: the query
    // anchor claimed within 10 m and 30 deg of an older anchor whose place is not near it (its
    // centre beyond twice place_radius_m in the current estimate), with a confident information.
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    if (unit(injection_random_) >= config_.injected_false_fraction) return;
    const Place &q = submaps_[query];
    const Eigen::Vector3d centre_q = graph_.T_world_node(query) * q.centre_anchor;
    std::vector<int> far;
    for (int c = 0; c < query; ++c)
        if (q.submap.path_start_m() - submaps_[c].submap.path_end_m() >= config_.min_loop_path_m &&
            (graph_.T_world_node(c) * submaps_[c].centre_anchor - centre_q).head<2>().norm() >
                2.0 * config_.place_radius_m)
            far.push_back(c);
    if (far.empty()) return;
    const int c = far[std::min<std::size_t>(
        far.size() - 1, static_cast<std::size_t>(unit(injection_random_) * far.size()))];
    Eigen::Isometry3d T_false = Eigen::Isometry3d::Identity();
    T_false.linear() =
        RotationFromRollPitchYaw({0.0, 0.0, (unit(injection_random_) - 0.5) * M_PI / 3.0});
    T_false.translation() << (unit(injection_random_) - 0.5) * 20.0,
        (unit(injection_random_) - 0.5) * 20.0, 0.0;
    RelativePoseEdge edge;
    edge.from = c;
    edge.to = query;
    edge.T_from_to = T_false;
    edge.information = (Vector6d() << 100.0, 100.0, 100.0, 1e4, 1e4, 1e4).finished().asDiagonal();
    edge.kind = EdgeKind::kLoop;
    LoopCandidate candidate;
    candidate.query_submap = query;
    candidate.candidate_submap = c;
    candidate.query_stamp_ns = q.submap.scans.front().stamp_ns;
    candidate.candidate_stamp_ns = submaps_[c].submap.scans.front().stamp_ns;
    candidate.path_between_m = q.submap.path_start_m() - submaps_[c].submap.path_end_m();
    candidate.distance_m =
        (graph_.T_world_node(c) * submaps_[c].centre_anchor - centre_q).head<2>().norm();
    candidate.verdict = CandidateVerdict::kInjected;
    candidate.edge = graph_.AddEdge(edge);
    candidates_.push_back(candidate);
    ++step.candidates;
    ++step.accepted;
}

}  // namespace dorado::loops
