// Loop verification by registration (loop_verification.hpp).
#include "dorado/loops/loop_verification.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <unordered_set>
#include <vector>
#include "dorado/core/require.hpp"

#include "dorado/mapping/voxel_key.hpp"
#include "point_grid.hpp"

namespace dorado::loops {

void VerificationConfig::Validate() const {
    const std::string k = "loop_closure.verify_";
    auto positive = [&](double v, const char *key) {
        Require(v > 0.0 && std::isfinite(v), k + key, "must be > 0");
    };
    positive(initial_threshold_m, "initial_threshold_m");
    positive(final_threshold_m, "final_threshold_m");
    positive(point_sigma_m, "point_sigma_m");
    positive(plane_flatness, "plane_flatness");
    positive(cluster_m, "cluster_m");
    positive(max_rms_m, "max_rms_m");
    positive(floor_sigma_translation_m, "floor_sigma_translation_m");
    positive(floor_sigma_rotation_rad, "floor_sigma_rotation_rad");
    Require(max_iterations >= 1, k + "max_iterations", "must be >= 1");
    Require(final_threshold_m <= initial_threshold_m, k + "final_threshold_m",
            "must not exceed verify_initial_threshold_m");
    Require(min_overlap >= 0.0 && min_overlap <= 1.0, k + "min_overlap", "must be in [0, 1]");
    Require(min_correspondences >= 6, k + "min_correspondences", "must be >= 6");
    Require(min_observability >= 0.0 && min_observability <= 1.0, k + "min_observability",
            "must be in [0, 1]");
}

const char *ToString(VerificationFailure failure) {
    switch (failure) {
        case VerificationFailure::kNone:
            return "";
        case VerificationFailure::kTooFewPoints:
            return "too few points";
        case VerificationFailure::kNotConverged:
            return "not converged";
        case VerificationFailure::kLowOverlap:
            return "low overlap";
        case VerificationFailure::kTooFewCorrespondences:
            return "too few correspondences";
        case VerificationFailure::kBadFitness:
            return "bad fitness";
        case VerificationFailure::kDegenerate:
            return "degenerate";
    }
    return "?";
}

namespace {

constexpr std::size_t kNeighbours = 10;  // of a candidate point's neighbourhood covariance
constexpr int kMaxQueryPoints = 600;     // the query is evenly thinned to at most this many
// The registration moves every axis of the pose (kAxes: the xi components it solves for; the
// others would keep the guess's, with a weak information, kHeldSigmaRad). Roll and pitch matter:
// the two visits' maps are tilted by the odometry's drift in pitch, a metre in height at the
// radar's range.
constexpr int kDof = 6;
constexpr int kAxes[kDof] = {0, 1, 2, 3, 4, 5};
constexpr int kPlanarAxes[3] = {0, 1, 5};  // x, y, yaw among kAxes
constexpr double kHeldSigmaRad = 0.5;
using Matrix4d = Eigen::Matrix<double, kDof, kDof>;
using Vector4d = Eigen::Matrix<double, kDof, 1>;

using Matrix3x6 = Eigen::Matrix<double, 3, 6>;

// The directions a neighbourhood with these eigenvalues (ascending) and eigenvectors fixes.
Eigen::Matrix3d ConstrainedDirections(const Eigen::Vector3d &lambda, const Eigen::Matrix3d &U) {
    constexpr double kThin = 0.1;       // an extent below this fraction of the next one is flat
    if (lambda(1) < kThin * lambda(2))  // a line along U.col(2)
        return Eigen::Matrix3d::Identity() - U.col(2) * U.col(2).transpose();
    if (lambda(0) < kThin * lambda(1)) return U.col(0) * U.col(0).transpose();  // a plane
    return Eigen::Matrix3d::Identity();
}

// The candidate's points and, described when first matched, each point's information W = C^-1,
// C the GICP regularisation of its neighbourhood's covariance: sigma^2 U diag(flatness, 1, 1) U^T
// with U the neighbourhood's eigenvectors, smallest first (a soft point-to-plane distance), and the
// directions its neighbourhood fixes (observability): its normal for a plane, the two across it
// for a line, every direction for a compact cluster.
class CandidateCloud {
  public:
    CandidateCloud(std::vector<Eigen::Vector3d> points, const VerificationConfig &config)
        : points_(std::move(points)),
          neighbourhoods_(points_, config.final_threshold_m),
          described_(points_.size(), false),
          information_(points_.size()),
          constrained_(points_.size()),
          config_(config) {}

    [[nodiscard]] const std::vector<Eigen::Vector3d> &points() const { return points_; }
    [[nodiscard]] const Eigen::Matrix3d &information(int i) { return Described(i).first; }
    [[nodiscard]] const Eigen::Matrix3d &constrained(int i) { return Described(i).second; }

  private:
    std::pair<const Eigen::Matrix3d &, const Eigen::Matrix3d &> Described(int i) {
        if (!described_[i]) Describe(i);
        return {information_[i], constrained_[i]};
    }

    void Describe(int i) {
        described_[i] = true;
        const double inv_sigma2 = 1.0 / (config_.point_sigma_m * config_.point_sigma_m);
        information_[i] = Eigen::Matrix3d::Identity() * inv_sigma2;
        constrained_[i] = Eigen::Matrix3d::Identity();
        const std::vector<int> neighbours = neighbourhoods_.KNearest(points_[i], kNeighbours);
        if (neighbours.size() < 5) return;
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        for (int j : neighbours) mean += points_[j];
        mean /= static_cast<double>(neighbours.size());
        Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
        for (int j : neighbours) {
            const Eigen::Vector3d d = points_[j] - mean;
            covariance += d * d.transpose();
        }
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
        const Eigen::Matrix3d &U = eigen.eigenvectors();
        const Eigen::Vector3d weights(1.0 / config_.plane_flatness, 1.0, 1.0);
        information_[i] = U * (weights * inv_sigma2).asDiagonal() * U.transpose();
        constrained_[i] = ConstrainedDirections(eigen.eigenvalues(), U);
    }

    std::vector<Eigen::Vector3d> points_;
    PointGrid neighbourhoods_;
    std::vector<bool> described_;
    std::vector<Eigen::Matrix3d> information_, constrained_;
    const VerificationConfig &config_;
};

struct LinearSystem {
    Matrix4d H = Matrix4d::Zero();  // over x, y, z, yaw
    Vector4d b = Vector4d::Zero();
    Matrix4d H_constrained = Matrix4d::Zero();  // sum J^T P J: what the structure fixes
    int correspondences = 0;
    double squared_distance = 0.0;  // sum |r|^2
    double mahalanobis = 0.0;       // sum r^T W r
    std::unordered_set<mapping::VoxelKey, mapping::VoxelKeyHash> cells;
};

// One Gauss-Newton system of the query points at T_candidate_query over kAxes (the right
// perturbation: T Exp(xi) p = R p + t + R rho - R Hat(p) phi, so J = [R, -R Hat(p)] restricted to
// those columns), Cauchy-weighted.
LinearSystem Linearise(CandidateCloud &candidate, const PointGrid &grid,
                       const std::vector<Eigen::Vector3d> &query, const Eigen::Isometry3d &T,
                       double threshold_m, double cluster_m) {
    LinearSystem system;
    const Eigen::Matrix3d R = T.rotation();
    for (const Eigen::Vector3d &p : query) {
        const Eigen::Vector3d p_candidate = T * p;
        const int nearest = grid.Nearest(p_candidate, threshold_m);
        if (nearest < 0) continue;
        const Eigen::Vector3d &q_candidate = candidate.points()[nearest];
        const Eigen::Vector3d r = p_candidate - q_candidate;
        const Eigen::Matrix3d &W = candidate.information(nearest);
        const double chi2 = r.dot(W * r);
        const double weight = 1.0 / (1.0 + chi2 / 9.0);  // Cauchy at 3 sigma
        Matrix3x6 J6;
        J6.leftCols<3>() = R;
        J6.rightCols<3>() = -R * Hat(p);
        Eigen::Matrix<double, 3, kDof> J;
        for (int a = 0; a < kDof; ++a) J.col(a) = J6.col(kAxes[a]);
        system.H += weight * J.transpose() * W * J;
        system.b += weight * J.transpose() * W * r;
        system.H_constrained += J.transpose() * candidate.constrained(nearest) * J;
        ++system.correspondences;
        system.squared_distance += r.squaredNorm();
        system.mahalanobis += chi2;
        system.cells.insert(mapping::VoxelKeyOf(q_candidate, cluster_m));
    }
    return system;
}

// Smallest / largest eigenvalue over x, y and yaw (the yaw in metres at the points' RMS radius) of
// the information of the matched structure (planes fix their normal, lines the directions across
// them): a corridor's walls leave the direction along them unobserved.
double HorizontalObservability(const Matrix4d &H4, const Eigen::Vector3d &centre, double radius_m) {
    Eigen::Matrix3d H;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) H(a, b) = H4(kPlanarAxes[a], kPlanarAxes[b]);
    // About the points' centre c instead of the anchor (a turn about a far anchor is mostly a
    // shift): dt = dt_c + dyaw (c_y, -c_x), then the yaw in metres at the RMS radius.
    Eigen::Matrix3d about_centre = Eigen::Matrix3d::Identity();
    about_centre(0, 2) = centre.y();
    about_centre(1, 2) = -centre.x();
    const Eigen::Vector3d scale(1.0, 1.0, 1.0 / std::max(radius_m, 1.0));
    H = scale.asDiagonal() * about_centre.transpose() * H * about_centre * scale.asDiagonal();
    const Eigen::Vector3d eigenvalues =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(H).eigenvalues();
    return eigenvalues(2) > 0.0 ? std::max(eigenvalues(0), 0.0) / eigenvalues(2) : 0.0;
}

// The registration's information over kAxes counted once per cell and scaled by the residuals'
// variance, inverted with the floor added; an axis it does not solve for gets kHeldSigmaRad's.
Matrix6d EdgeInformation(const LinearSystem &system, const VerificationConfig &config) {
    const double per_cell =
        static_cast<double>(system.cells.size()) / std::max(system.correspondences, 1);
    const double variance_scale =
        std::max(1.0, system.mahalanobis / (3.0 * system.correspondences));
    const Matrix4d H = system.H * per_cell / variance_scale;
    const Eigen::SelfAdjointEigenSolver<Matrix4d> eigen(H);
    const double largest = std::max(eigen.eigenvalues().maxCoeff(), 1e-12);
    const Vector4d inverse = eigen.eigenvalues().cwiseMax(largest * 1e-9).cwiseInverse();
    Matrix4d covariance =
        eigen.eigenvectors() * inverse.asDiagonal() * eigen.eigenvectors().transpose();
    const double t2 = config.floor_sigma_translation_m * config.floor_sigma_translation_m;
    const double r2 = config.floor_sigma_rotation_rad * config.floor_sigma_rotation_rad;
    for (int a = 0; a < kDof; ++a) covariance(a, a) += kAxes[a] < 3 ? t2 : r2;
    const Matrix4d reduced = covariance.inverse();
    Matrix6d information = Matrix6d::Zero();
    for (int a = 0; a < kDof; ++a)
        for (int b = 0; b < kDof; ++b)
            information(kAxes[a], kAxes[b]) = 0.5 * (reduced(a, b) + reduced(b, a));
    for (int axis = 0; axis < 6; ++axis)
        if (information(axis, axis) == 0.0)
            information(axis, axis) = 1.0 / (kHeldSigmaRad * kHeldSigmaRad);
    return information;
}

// The height offset that most query points agree with: each query point votes for the height
// differences to the candidate points above or below it (within 0.5 m in the plane), in 0.25 m
// bins; the fullest bin wins (the ground's and the walls' offsets agree, their spread does not).
double HeightOffset(const std::vector<Eigen::Vector3d> &candidate,
                    const std::vector<Eigen::Vector3d> &query, const Eigen::Isometry3d &T) {
    constexpr double kBinM = 0.25, kRangeM = 20.0, kColumnM = 0.5;
    std::vector<Eigen::Vector3d> flat(candidate);
    for (Eigen::Vector3d &p : flat) p.z() = 0.0;
    const PointGrid columns(flat, kColumnM);
    std::vector<int> votes(static_cast<std::size_t>(2.0 * kRangeM / kBinM), 0);
    for (const Eigen::Vector3d &p : query) {
        const Eigen::Vector3d p_candidate = T * p;
        for (int i : columns.KNearest({p_candidate.x(), p_candidate.y(), 0.0}, 8)) {
            const double dz = candidate[i].z() - p_candidate.z();
            const auto bin = static_cast<long>(std::floor((dz + kRangeM) / kBinM));
            if (bin >= 0 && bin < static_cast<long>(votes.size())) ++votes[bin];
        }
    }
    const auto best = std::max_element(votes.begin(), votes.end()) - votes.begin();
    return *std::max_element(votes.begin(), votes.end()) > 0 ? (best + 0.5) * kBinM - kRangeM : 0.0;
}

Vector6d Step(const Vector4d &delta) {
    Vector6d xi = Vector6d::Zero();
    for (int a = 0; a < kDof; ++a) xi(kAxes[a]) = delta(a);
    return xi;
}

}  // namespace

Verification VerifyLoop(const Eigen::Matrix3Xf &candidate_points,
                        const Eigen::Matrix3Xf &query_points,
                        const Eigen::Isometry3d &T_candidate_query_guess,
                        const VerificationConfig &config) {
    Verification result;
    result.T_candidate_query = T_candidate_query_guess;
    if (candidate_points.cols() < config.min_correspondences ||
        query_points.cols() < config.min_correspondences)
        return result;  // kTooFewPoints
    std::vector<Eigen::Vector3d> candidate_list(static_cast<std::size_t>(candidate_points.cols()));
    for (Eigen::Index i = 0; i < candidate_points.cols(); ++i)
        candidate_list[static_cast<std::size_t>(i)] = candidate_points.col(i).cast<double>();
    CandidateCloud candidate(std::move(candidate_list), config);
    // Two grids: the first iterations' wide search, then the final threshold's.
    const PointGrid coarse(candidate.points(), config.initial_threshold_m);
    const PointGrid fine(candidate.points(), config.final_threshold_m);
    std::vector<Eigen::Vector3d> query;
    const Eigen::Index step = std::max<Eigen::Index>(1, query_points.cols() / kMaxQueryPoints);
    for (Eigen::Index i = 0; i < query_points.cols(); i += step)
        query.push_back(query_points.col(i).cast<double>());
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d &p : query) centre += p;
    centre /= static_cast<double>(query.size());
    double radius2 = 0.0;
    for (const Eigen::Vector3d &p : query) radius2 += (p - centre).head<2>().squaredNorm();
    const double radius_m = std::sqrt(radius2 / static_cast<double>(query.size()));

    Eigen::Isometry3d T = T_candidate_query_guess;
    // The guess's height is the odometry's, which drifts by metres over a lap: start at the height
    // the points agree on (in the candidate's frame).
    T.translation().z() += HeightOffset(candidate.points(), query, T);
    bool converged = false;
    const int shrink = std::max(1, config.max_iterations / 2);
    for (int iteration = 0; iteration < config.max_iterations; ++iteration) {
        const double alpha = std::min(1.0, static_cast<double>(iteration) / shrink);
        const double threshold = config.initial_threshold_m +
                                 alpha * (config.final_threshold_m - config.initial_threshold_m);
        const LinearSystem system = Linearise(candidate, alpha < 1.0 ? coarse : fine, query, T,
                                              threshold, config.cluster_m);
        result.iterations = iteration + 1;
        if (system.correspondences < 6) break;
        const Vector4d delta = -system.H.ldlt().solve(system.b);
        if (!delta.allFinite()) break;
        T = T * ExpSE3(Step(delta));
        if (alpha >= 1.0 && Step(delta).head<3>().norm() < 1e-2 &&
            Step(delta).tail<3>().norm() < 5e-4) {
            converged = true;
            break;
        }
    }
    result.T_candidate_query = T;
    const LinearSystem final_system =
        Linearise(candidate, fine, query, T, config.final_threshold_m, config.cluster_m);
    result.correspondences = final_system.correspondences;
    result.overlap =
        static_cast<double>(final_system.correspondences) / static_cast<double>(query.size());
    result.rms_m = final_system.correspondences > 0
                       ? std::sqrt(final_system.squared_distance / final_system.correspondences)
                       : 0.0;
    result.observability = HorizontalObservability(final_system.H_constrained, centre, radius_m);
    if (final_system.correspondences >= 6)
        result.information = EdgeInformation(final_system, config);
    if (!converged)
        result.failure = VerificationFailure::kNotConverged;
    else if (result.overlap < config.min_overlap)
        result.failure = VerificationFailure::kLowOverlap;
    else if (result.correspondences < config.min_correspondences)
        result.failure = VerificationFailure::kTooFewCorrespondences;
    else if (result.rms_m > config.max_rms_m)
        result.failure = VerificationFailure::kBadFitness;
    else if (result.observability < config.min_observability)
        result.failure = VerificationFailure::kDegenerate;
    else
        result.failure = VerificationFailure::kNone;
    return result;
}

}  // namespace dorado::loops
