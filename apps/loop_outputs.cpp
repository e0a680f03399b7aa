#include "loop_outputs.hpp"

#include <cmath>
#include <cstdio>
#include <map>

#include "dorado/core/time.hpp"
#include "dorado/io/atomic_file.hpp"
#include "dorado/io/csv_text.hpp"
#include "dorado/io/trajectory_io.hpp"
#include "reference_path.hpp"

namespace dorado::apps {
namespace {

constexpr const char *kLoopsHeader =
    "query_submap,candidate_submap,query_t,candidate_t,query_x_m,query_y_m,candidate_x_m,"
    "candidate_y_m,path_between_m,distance_m,gate_m,descriptor_distance,place_matches,"
    "place_inliers,place_x_m,place_y_m,place_yaw_deg,overlap,correspondences,rms_m,"
    "observability,sigma_x_m,sigma_y_m,sigma_yaw_deg,consistency_chi2,loop_x_m,loop_y_m,loop_z_m,"
    "loop_yaw_deg,switch,detect_ms,verify_ms,verdict\n";

constexpr double kDeg = 180.0 / M_PI;

std::string CandidateRow(const loops::LoopCandidate &c, const loops::LoopCloser &closer) {
    const Eigen::Vector3d q = closer.T_world_anchor_written(c.query_submap).translation();
    const Eigen::Vector3d k = closer.T_world_anchor_written(c.candidate_submap).translation();
    char row[1024];
    int n = std::snprintf(row, sizeof(row),
                          "%d,%d,%.9f,%.9f,%.3f,%.3f,%.3f,%.3f,%.2f,%.2f,%.2f,%.2f,%d,%d,%.3f,%.3f,"
                          "%.2f,",
                          c.query_submap, c.candidate_submap, NanosToSeconds(c.query_stamp_ns),
                          NanosToSeconds(c.candidate_stamp_ns), q.x(), q.y(), k.x(), k.y(),
                          c.path_between_m, c.distance_m, c.gate_m, c.place.descriptor_distance,
                          c.place.matches, c.place.inliers, c.place.xy_yaw_candidate_query.x(),
                          c.place.xy_yaw_candidate_query.y(),
                          c.place.xy_yaw_candidate_query.z() * kDeg);
    std::string text(row, static_cast<std::size_t>(n));
    if (c.verification) {
        const loops::Verification &v = *c.verification;
        const Matrix6d covariance = v.information.inverse();
        const Eigen::Vector3d rpy = RollPitchYaw(v.T_candidate_query.rotation());
        const Eigen::Vector3d t = v.T_candidate_query.translation();
        n = std::snprintf(row, sizeof(row),
                          "%.3f,%d,%.3f,%.4f,%.4f,%.4f,%.4f,%.3f,%.3f,%.3f,%.3f,%.3f,", v.overlap,
                          v.correspondences, v.rms_m, v.observability, std::sqrt(covariance(0, 0)),
                          std::sqrt(covariance(1, 1)), std::sqrt(covariance(5, 5)) * kDeg,
                          c.consistency_chi2, t.x(), t.y(), t.z(), rpy.z() * kDeg);
        text.append(row, static_cast<std::size_t>(n));
    } else {
        text += ",,,,,,,,,,,,";
    }
    n = std::snprintf(row, sizeof(row), "%s,%.3f,%.3f,",
                      c.edge >= 0 ? std::to_string(c.switch_value).c_str() : "", c.detect_ms,
                      c.verify_ms);
    text.append(row, static_cast<std::size_t>(n));
    return text + io::CsvQuoted(loops::VerdictText(c)) + "\n";
}

}  // namespace

nlohmann::json FinishMapRun(const std::string &out_dir, const io::DatasetConfig &dataset,
                            const std::vector<mapping::WrittenPose> &last,
                            const Trajectory &written, MapOutputs &outputs, LoopOutputs *loops) {
    outputs.AddWritten(last);
    if (loops == nullptr) {
        outputs.Write(out_dir, written, ReferencePath(dataset, written));
        return false;
    }
    loops->Add(last);
    loops->Finish();
    io::WriteTum(out_dir + "/trajectory_uncorrected.tum", written);
    const Trajectory corrected = loops->CorrectedTrajectory();
    const MapCorrection correction{loops->Corrections(), loops->AcceptedLoopsWorld()};
    outputs.Write(out_dir, corrected, ReferencePath(dataset, corrected), &correction);
    loops->Write(out_dir);
    return loops->Summary();
}

std::string G2oText(const loops::PoseGraph &graph) {
    std::string text =
        "# dorado's loop closure graph: one vertex per submap anchor (corrected), "
        "odometry and loop edges\n";
    char line[1024];
    for (int i = 0; i < graph.nodes(); ++i) {
        const Eigen::Isometry3d T = graph.T_world_node(i);
        const Eigen::Quaterniond q(T.rotation());
        std::snprintf(line, sizeof(line), "VERTEX_SE3:QUAT %d %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n",
                      i, T.translation().x(), T.translation().y(), T.translation().z(), q.x(),
                      q.y(), q.z(), q.w());
        text += line;
    }
    if (graph.nodes() > 0) text += "FIX 0\n";
    // g2o's error is [dp; vec(dq)] with vec(dq) = phi / 2: its information is D Lambda D, D =
    // diag(1, 1, 1, 2, 2, 2).
    const Vector6d d = (Vector6d() << 1.0, 1.0, 1.0, 2.0, 2.0, 2.0).finished();
    for (std::size_t e = 0; e < graph.edges().size(); ++e) {
        const loops::RelativePoseEdge &edge = graph.edges()[e];
        if (edge.kind == loops::EdgeKind::kLoop) {
            std::snprintf(line, sizeof(line), "# loop edge, switch %.3f\n",
                          graph.switch_value(static_cast<int>(e)));
            text += line;
        }
        const Eigen::Quaterniond q(edge.T_from_to.rotation());
        const Eigen::Vector3d &t = edge.T_from_to.translation();
        std::snprintf(line, sizeof(line), "EDGE_SE3:QUAT %d %d %.6f %.6f %.6f %.9f %.9f %.9f %.9f",
                      edge.from, edge.to, t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
        text += line;
        const Matrix6d information = d.asDiagonal() * edge.information * d.asDiagonal();
        for (int r = 0; r < 6; ++r)
            for (int c = r; c < 6; ++c) {
                std::snprintf(line, sizeof(line), " %.9g", information(r, c));
                text += line;
            }
        text += "\n";
    }
    return text;
}

LoopOutputs::LoopOutputs(const loops::LoopClosureConfig &config) : closer_(config) {}

void LoopOutputs::Add(const std::vector<mapping::WrittenPose> &written) {
    for (const mapping::WrittenPose &pose : written) {
        const Eigen::Vector3d p = pose.T_world_base.translation();
        if (last_position_.allFinite()) path_m_ += (p - last_position_).norm();
        last_position_ = p;
        const loops::LoopStep step = closer_.Add(pose);
        if (!step.submap_closed) continue;
        submap_ms_.push_back(step.describe_ms + step.detect_ms + step.verify_ms);
        if (step.solution) {
            ++solves_;
            solve_ms_.push_back(step.solution->solve_ms);
        }
    }
}

void LoopOutputs::Finish() {
    const loops::LoopStep step = closer_.Finish();
    if (!step.submap_closed) return;
    submap_ms_.push_back(step.describe_ms + step.detect_ms + step.verify_ms);
    if (step.solution) {
        ++solves_;
        solve_ms_.push_back(step.solution->solve_ms);
    }
}

std::vector<LoopEdge> LoopOutputs::AcceptedLoopsWorld() const {
    std::vector<LoopEdge> edges;
    for (const loops::LoopCandidate &c : closer_.candidates()) {
        if (c.verdict != loops::CandidateVerdict::kAccepted) continue;
        edges.push_back({closer_.graph().T_world_node(c.candidate_submap).translation(),
                         closer_.graph().T_world_node(c.query_submap).translation()});
    }
    return edges;
}

void LoopOutputs::Write(const std::string &out_dir) const {
    io::WriteFileAtomically(out_dir + "/loops.csv", [&](std::ostream &os) {
        os << kLoopsHeader;
        for (const loops::LoopCandidate &c : closer_.candidates()) os << CandidateRow(c, closer_);
    });
    io::WriteFileAtomically(out_dir + "/graph.g2o",
                            [&](std::ostream &os) { os << G2oText(closer_.graph()); });
}

nlohmann::json LoopOutputs::Summary() const {
    std::map<std::string, int> verdicts;
    for (const loops::LoopCandidate &c : closer_.candidates()) verdicts[loops::VerdictText(c)]++;
    const double bytes = static_cast<double>(closer_.submap_bytes());
    return {{"submaps", closer_.submaps()},
            {"candidates", closer_.candidates().size()},
            {"loops_accepted", closer_.loops_accepted()},
            {"candidates_by_verdict", verdicts},
            {"time_per_submap_ms", TimeStatistics(submap_ms_)},
            {"graph_solves", solves_},
            {"graph_solve_ms", TimeStatistics(solve_ms_)},
            {"submaps_mb", bytes / 1e6},
            {"submaps_mb_per_km", path_m_ > 0.0 ? bytes / 1e6 / (path_m_ / 1000.0) : 0.0}};
}

}  // namespace dorado::apps
