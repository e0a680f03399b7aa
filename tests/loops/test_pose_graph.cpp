// The anchors' pose graph against optima known in closed form or by construction.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "dorado/core/lie.hpp"
#include "dorado/loops/pose_graph.hpp"

namespace dorado::loops {
namespace {

Eigen::Isometry3d Translation(double x, double y = 0.0) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() << x, y, 0.0;
    return T;
}

Eigen::Isometry3d Planar(double x, double y, double yaw) {
    Eigen::Isometry3d T = Translation(x, y);
    T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return T;
}

RelativePoseEdge Edge(int from, int to, const Eigen::Isometry3d &T, double sigma_m,
                      double sigma_rad, EdgeKind kind = EdgeKind::kOdometry) {
    RelativePoseEdge edge;
    edge.from = from;
    edge.to = to;
    edge.T_from_to = T;
    const double a = 1.0 / (sigma_m * sigma_m), b = 1.0 / (sigma_rad * sigma_rad);
    edge.information = (Vector6d() << a, a, a, b, b, b).finished().asDiagonal();
    edge.kind = kind;
    return edge;
}

// Three nodes on a line, three equally weighted measurements 0->1: 1, 1->2: 1, 0->2: 2.3 (node 0
// held): least squares (x1 - 1)^2 + (x2 - x1 - 1)^2 + (x2 - 2.3)^2 is least at x1 = 1.1, x2 = 2.2.
TEST(PoseGraph, LinearChainReachesTheLeastSquaresOptimum) {
    PoseGraph graph;
    graph.AddNode(Translation(0.0));
    graph.AddNode(Translation(0.7, 0.3));
    graph.AddNode(Translation(2.9, -0.4));
    graph.AddEdge(Edge(0, 1, Translation(1.0), 0.1, 0.01));
    graph.AddEdge(Edge(1, 2, Translation(1.0), 0.1, 0.01));
    graph.AddEdge(Edge(0, 2, Translation(2.3), 0.1, 0.01));
    const PoseGraphSolution solution = graph.Optimize(PoseGraphConfig{});
    EXPECT_TRUE(solution.converged);
    EXPECT_NEAR(graph.T_world_node(1).translation().x(), 1.1, 1e-6);
    EXPECT_NEAR(graph.T_world_node(2).translation().x(), 2.2, 1e-6);
    EXPECT_NEAR(graph.T_world_node(2).translation().y(), 0.0, 1e-6);
    EXPECT_NEAR(graph.T_world_node(0).translation().x(), 0.0, 1e-12);  // the gauge
}

// A ring of consistent measurements: from a perturbed start the graph returns to the truth.
TEST(PoseGraph, ConsistentRingReturnsToTheTruth) {
    std::mt19937 random(3);
    std::normal_distribution<double> noise(0.0, 0.3);
    std::vector<Eigen::Isometry3d> truth;
    for (int k = 0; k < 12; ++k)
        truth.push_back(Planar(20.0 * std::cos(k * M_PI / 6.0), 20.0 * std::sin(k * M_PI / 6.0),
                               k * M_PI / 6.0 + M_PI / 2.0));
    PoseGraph graph;
    for (int k = 0; k < 12; ++k)
        graph.AddNode(k == 0
                          ? truth[0]
                          : truth[k] * Planar(noise(random), noise(random), 0.1 * noise(random)));
    for (int k = 0; k < 12; ++k) {
        const int next = (k + 1) % 12;
        graph.AddEdge(Edge(k, next, truth[k].inverse() * truth[next], 0.1, 0.01));
    }
    graph.Optimize(PoseGraphConfig{});
    for (int k = 0; k < 12; ++k)
        EXPECT_LT((graph.T_world_node(k).translation() - truth[k].translation()).norm(), 1e-5) << k;
}

// A square drive, its odometry biased in yaw: a true loop edge pulls the last node back to the
// first; a false one (10 m off) on an exact odometry is switched off and bends nothing.
struct Square {
    std::vector<Eigen::Isometry3d> truth, odometry;
    Square(double yaw_bias_rad) {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity(), T_odometry = T;
        for (int k = 0; k <= 40; ++k) {
            truth.push_back(T);
            odometry.push_back(T_odometry);
            const Eigen::Isometry3d step = Planar(10.0, 0.0, k % 10 == 9 ? M_PI / 2.0 : 0.0);
            T = T * step;
            T_odometry = T_odometry * step * Planar(0.0, 0.0, yaw_bias_rad);
        }
    }
    PoseGraph Graph() const {
        PoseGraph graph;
        for (const auto &T : odometry) graph.AddNode(T);
        for (std::size_t k = 0; k + 1 < odometry.size(); ++k)
            graph.AddEdge(Edge(static_cast<int>(k), static_cast<int>(k + 1),
                               odometry[k].inverse() * odometry[k + 1], 0.05, 0.005));
        return graph;
    }
};

TEST(PoseGraph, TrueLoopEdgeRemovesTheDrift) {
    // A bias the odometry's covariance allows (0.002 rad a step against 0.005 rad noise).
    const Square square(0.002);
    PoseGraph graph = square.Graph();
    const double drift =
        (square.odometry[40].translation() - square.truth[40].translation()).norm();
    ASSERT_GT(drift, 5.0);
    const int loop = graph.AddEdge(
        Edge(0, 40, square.truth[0].inverse() * square.truth[40], 0.05, 0.002, EdgeKind::kLoop));
    graph.Optimize(PoseGraphConfig{});
    EXPECT_GT(graph.switch_value(loop), 0.9);
    EXPECT_LT((graph.T_world_node(40).translation() - square.truth[40].translation()).norm(), 0.2);
}

TEST(PoseGraph, FalseLoopEdgeIsSwitchedOffAndBendsNothing) {
    const Square square(0.0);
    PoseGraph graph = square.Graph();
    const int loop =
        graph.AddEdge(Edge(0, 25, Planar(3.0, 8.0, 0.3), 0.05, 0.002, EdgeKind::kLoop));
    graph.Optimize(PoseGraphConfig{});
    EXPECT_LT(graph.switch_value(loop), 0.5);
    for (int k = 0; k <= 40; ++k)
        EXPECT_LT((graph.T_world_node(k).translation() - square.truth[k].translation()).norm(), 0.1)
            << k;
}

TEST(PoseGraph, RejectsEdgesToUnknownNodesAndBadInformation) {
    PoseGraph graph;
    graph.AddNode(Translation(0.0));
    graph.AddNode(Translation(1.0));
    EXPECT_THROW(graph.AddEdge(Edge(0, 2, Translation(1.0), 0.1, 0.01)), std::invalid_argument);
    RelativePoseEdge edge = Edge(0, 1, Translation(1.0), 0.1, 0.01);
    edge.information(0, 0) = std::nan("");
    EXPECT_THROW(graph.AddEdge(edge), std::invalid_argument);
    edge.information = -Matrix6d::Identity();
    EXPECT_THROW(graph.AddEdge(edge), std::invalid_argument);
}

}  // namespace
}  // namespace dorado::loops
