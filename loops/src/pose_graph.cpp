// The anchors' pose graph in Ceres (pose_graph.hpp).
#include "dorado/loops/pose_graph.hpp"

#include <ceres/ceres.h>

#include <chrono>
#include <cmath>
#include <stdexcept>

#include <string>
#include "dorado/core/require.hpp"

#include "pose_graph_residuals.hpp"

namespace dorado::loops {

void PoseGraphConfig::Validate() const {
    Require(loop_loss_scale > 0.0 && std::isfinite(loop_loss_scale),
            "loop_closure.graph_loop_loss_scale", "must be > 0");
    Require(switch_prior_sigma > 0.0 && std::isfinite(switch_prior_sigma),
            "loop_closure.graph_switch_prior_sigma", "must be > 0");
    Require(max_iterations >= 1, "loop_closure.graph_max_iterations", "must be >= 1");
}

int PoseGraph::AddNode(const Eigen::Isometry3d &T_world_node) {
    nodes_.push_back({T_world_node.translation(), Eigen::Quaterniond(T_world_node.rotation())});
    return nodes() - 1;
}

int PoseGraph::AddEdge(const RelativePoseEdge &edge) {
    if (edge.from < 0 || edge.from >= nodes() || edge.to < 0 || edge.to >= nodes() ||
        edge.from == edge.to)
        throw std::invalid_argument("pose graph edge " + std::to_string(edge.from) + " -> " +
                                    std::to_string(edge.to) + ": no such pair of nodes");
    const bool finite = edge.information.allFinite() && edge.T_from_to.matrix().allFinite();
    if (!finite || !edge.information.isApprox(edge.information.transpose(), 1e-9) ||
        edge.information.llt().info() != Eigen::Success)
        throw std::invalid_argument("pose graph edge " + std::to_string(edge.from) + " -> " +
                                    std::to_string(edge.to) +
                                    ": the information is not finite, symmetric and positive");
    edges_.push_back(edge);
    switches_.push_back(1.0);
    return static_cast<int>(edges_.size()) - 1;
}

Eigen::Isometry3d PoseGraph::T_world_node(int node) const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = nodes_.at(node).q_world.normalized().toRotationMatrix();
    T.translation() = nodes_.at(node).p_world;
    return T;
}

PoseGraphSolution PoseGraph::Optimize(const PoseGraphConfig &config) {
    const auto start = std::chrono::steady_clock::now();
    PoseGraphSolution solution;
    if (nodes_.size() < 2) return solution;
    ceres::Problem::Options problem_options;
    problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem_options.loss_function_ownership = ceres::TAKE_OWNERSHIP;
    ceres::Problem problem(problem_options);
    ceres::EigenQuaternionManifold quaternion;
    for (std::size_t e = 0; e < edges_.size(); ++e) {
        const RelativePoseEdge &edge = edges_[e];
        Node &a = nodes_[edge.from], &b = nodes_[edge.to];
        const Matrix6d sqrt_information = SqrtInformation(edge.information);
        if (edge.kind == EdgeKind::kOdometry) {
            problem.AddResidualBlock(PoseGraph3dErrorTerm::Create(edge.T_from_to, sqrt_information),
                                     nullptr, a.p_world.data(), a.q_world.coeffs().data(),
                                     b.p_world.data(), b.q_world.coeffs().data());
        } else {
            double *s = &switches_[e];
            problem.AddResidualBlock(
                SwitchableLoopErrorTerm::Create(edge.T_from_to, sqrt_information),
                new ceres::CauchyLoss(config.loop_loss_scale), a.p_world.data(),
                a.q_world.coeffs().data(), b.p_world.data(), b.q_world.coeffs().data(), s);
            problem.AddResidualBlock(SwitchPriorErrorTerm::Create(config.switch_prior_sigma),
                                     nullptr, s);
            problem.SetParameterLowerBound(s, 0, 0.0);
            problem.SetParameterUpperBound(s, 0, 1.0);
        }
    }
    for (Node &node : nodes_)
        if (problem.HasParameterBlock(node.q_world.coeffs().data()))
            problem.SetManifold(node.q_world.coeffs().data(), &quaternion);
    // The graph's measurements are all relative: its pose in the world is fixed by holding the
    // first node where the mapper put it (the gauge); every correction moves the later nodes.
    if (!problem.HasParameterBlock(nodes_[0].p_world.data())) return solution;
    problem.SetParameterBlockConstant(nodes_[0].p_world.data());
    problem.SetParameterBlockConstant(nodes_[0].q_world.coeffs().data());

    ceres::Solver::Options options;
    options.max_num_iterations = config.max_iterations;
    options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    options.num_threads = 1;
    // A graph of a few hundred anchors solves in milliseconds: solve it to convergence.
    options.function_tolerance = 1e-10;
    options.gradient_tolerance = 1e-12;
    options.parameter_tolerance = 1e-10;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    for (Node &node : nodes_) node.q_world.normalize();
    solution.converged = summary.termination_type == ceres::CONVERGENCE;
    solution.iterations = static_cast<int>(summary.iterations.size());
    solution.initial_cost = summary.initial_cost;
    solution.final_cost = summary.final_cost;
    solution.solve_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return solution;
}

}  // namespace dorado::loops
