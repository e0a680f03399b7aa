#pragma once
/// @file pose_graph.hpp
/// A pose graph over submap anchors, solved with Ceres (after Ceres' examples/slam/pose_graph_3d):
/// odometry edges between consecutive anchors carry the smoother's relative covariance; loop
/// edges carry their registration's information, a robust loss and a switch variable s in [0, 1]
/// (switchable constraints, Suenderhauf and Protzel 2012) that scales the edge's residual and is
/// pulled towards 1 by a prior: an edge that disagrees with the rest of the graph is switched off
/// instead of bending it. The first node is held fixed (the gauge).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "dorado/core/lie.hpp"

namespace dorado::loops {

enum class EdgeKind { kOdometry, kLoop };

/// A measured relative pose T_from_to with the information of its error xi, the right
/// perturbation in the `to` node's frame: T_from_to_true = T_from_to ExpSE3(xi), xi = [rho; phi].
struct RelativePoseEdge {
    int from = 0;
    int to = 0;
    Eigen::Isometry3d T_from_to = Eigen::Isometry3d::Identity();
    Matrix6d information = Matrix6d::Identity();
    EdgeKind kind = EdgeKind::kOdometry;
};

struct PoseGraphConfig {
    double loop_loss_scale = 3.0;  ///< Cauchy scale of a loop edge, in whitened units (sigmas)
    /// A switch's prior (1 - s) / sigma: an edge stays on while the graph's cost of agreeing with
    /// it stays below 1 / sigma^2 (0.2: 25, about the consistency gate's 22.5).
    double switch_prior_sigma = 0.2;
    int max_iterations = 100;
    /// Throws std::invalid_argument naming the first bad key.
    void Validate() const;
};

struct PoseGraphSolution {
    bool converged = false;
    int iterations = 0;
    double initial_cost = 0.0;
    double final_cost = 0.0;
    double solve_ms = 0.0;
};

class PoseGraph {
  public:
    /// Adds a node at its initial pose; returns its index (0, 1, ...).
    int AddNode(const Eigen::Isometry3d &T_world_node);
    /// Adds an edge between existing nodes; returns its index. Throws std::invalid_argument on an
    /// unknown node or a non-finite / non-symmetric-positive information.
    int AddEdge(const RelativePoseEdge &edge);

    /// Solves for every node but the first. The loop edges' switches are solved with them.
    PoseGraphSolution Optimize(const PoseGraphConfig &config);

    [[nodiscard]] int nodes() const { return static_cast<int>(nodes_.size()); }
    [[nodiscard]] Eigen::Isometry3d T_world_node(int node) const;
    [[nodiscard]] const std::vector<RelativePoseEdge> &edges() const { return edges_; }
    /// The switch of a loop edge after the last Optimize (1: fully on; odometry edges: 1).
    [[nodiscard]] double switch_value(int edge) const { return switches_[edge]; }

  private:
    struct Node {
        Eigen::Vector3d p_world;
        Eigen::Quaterniond q_world;  // Eigen's x y z w storage, on ceres::EigenQuaternionManifold
    };
    std::vector<Node> nodes_;
    std::vector<RelativePoseEdge> edges_;
    std::vector<double> switches_;  // one per edge
};

}  // namespace dorado::loops
