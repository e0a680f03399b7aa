#pragma once
/// @file loop_outputs.hpp
/// Loop closure in `dorado map`: the written poses go to a loops::LoopCloser as they leave the
/// smoother (after their scan's registration, never before it), and its results are written:
/// loops.csv (every candidate: the two places, the descriptor's and the verification's numbers,
/// accepted or why not), graph.g2o (the anchors' pose graph in g2o's text format, corrected), and
/// the corrections that trajectory.tum, the map files and map.png take.

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "dorado/io/dataset_config.hpp"
#include "dorado/loops/loop_closer.hpp"
#include "map_image.hpp"
#include "map_outputs.hpp"

namespace dorado::apps {

class LoopOutputs {
  public:
    explicit LoopOutputs(const loops::LoopClosureConfig &config);

    /// Feeds written poses (in order).
    void Add(const std::vector<mapping::WrittenPose> &written);
    /// The end of the drive: the last submap's loops.
    void Finish();

    /// Per written pose, in order: corrected T_world_base = correction * written T_world_base.
    [[nodiscard]] std::vector<Eigen::Isometry3d> Corrections() const {
        return closer_.Corrections();
    }
    [[nodiscard]] Trajectory CorrectedTrajectory() const { return closer_.CorrectedTrajectory(); }
    /// The accepted loops as map.png draws them (the places' corrected centres).
    [[nodiscard]] std::vector<LoopEdge> AcceptedLoopsWorld() const;

    /// Writes loops.csv and graph.g2o into out_dir.
    void Write(const std::string &out_dir) const;
    /// summary.json's "loop_closure": submaps, candidates and loops by verdict, time per submap
    /// (detection and verification), the graph's solves, the submaps' memory.
    [[nodiscard]] nlohmann::json Summary() const;

  private:
    loops::LoopCloser closer_;
    std::vector<double> submap_ms_;  // describe + detect + verify, per complete submap
    std::vector<double> solve_ms_;
    int solves_ = 0;
    double path_m_ = 0.0;
    Eigen::Vector3d last_position_ = Eigen::Vector3d::Constant(NAN);
};

/// The end of a map run: the poses still in the smoother (`last`) into the outputs and the loop
/// closer (none: no loop closure), then the files: trajectory.tum and the map as written, or with
/// loop closure corrected, with trajectory_uncorrected.tum (`written`), loops.csv and graph.g2o.
/// Returns summary.json's "loop_closure" (false without).
nlohmann::json FinishMapRun(const std::string &out_dir, const io::DatasetConfig &dataset,
                            const std::vector<mapping::WrittenPose> &last,
                            const Trajectory &written, MapOutputs &outputs, LoopOutputs *loops);

/// The graph in g2o's text format: VERTEX_SE3:QUAT per anchor (corrected), EDGE_SE3:QUAT per
/// edge with its information converted to g2o's error [dp; vec(dq)] (the rotation rows doubled:
/// vec(dq) = phi / 2); a comment line before each loop edge gives its switch.
[[nodiscard]] std::string G2oText(const loops::PoseGraph &graph);

}  // namespace dorado::apps
