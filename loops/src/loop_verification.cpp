// Loop verification by registration (loop_verification.hpp).
#include "dorado/loops/loop_verification.hpp"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_set>
#include <vector>

#include "dorado/mapping/voxel_key.hpp"

namespace dorado::loops {

void VerificationConfig::Validate() const {
    auto positive = [](double v, const char *key) {
        if (!(v > 0.0) || !std::isfinite(v))
            throw std::invalid_argument(std::string("loop_closure.") + key + ": must be > 0");
    };
    positive(initial_threshold_m, "verify_initial_threshold_m");
    positive(final_threshold_m, "verify_final_threshold_m");
    positive(point_sigma_m, "verify_point_sigma_m");
    positive(plane_flatness, "verify_plane_flatness");
    positive(cluster_m, "verify_cluster_m");
    positive(max_rms_m, "verify_max_rms_m");
    positive(floor_sigma_translation_m, "verify_floor_sigma_translation_m");
    positive(floor_sigma_rotation_rad, "verify_floor_sigma_rotation_rad");
    if (max_iterations < 1) throw std::invalid_argument("loop_closure.verify_max_iterations: must be >= 1");
    if (final_threshold_m > initial_threshold_m)
        throw std::invalid_argument(
            "loop_closure.verify_final_threshold_m: must not exceed verify_initial_threshold_m");
    if (!(min_overlap >= 0.0 && min_overlap <= 1.0))
        throw std::invalid_argument("loop_closure.verify_min_overlap: must be in [0, 1]");
    if (min_correspondences < 6)
        throw std::invalid_argument("loop_closure.verify_min_correspondences: must be >= 6");
    if (!(min_observability >= 0.0 && min_observability <= 1.0))
        throw std::invalid_argument("loop_closure.verify_min_observability: must be in [0, 1]");
}

const char *ToString(VerificationFailure failure) {
    switch (failure) {
        case VerificationFailure::kNone: return "";
        case VerificationFailure::kTooFewPoints: return "too few points";
        case VerificationFailure::kNotConverged: return "not converged";
        case VerificationFailure::kLowOverlap: return "low overlap";
        case VerificationFailure::kTooFewCorrespondences: return "too few correspondences";
        case VerificationFailure::kBadFitness: return "bad fitness";
        case VerificationFailure::kDegenerate: return "degenerate";
    }
    return "?";
}

namespace {

constexpr int kNeighbours = 10;          // of a candidate point's neighbourhood covariance
constexpr int kMaxQueryPoints = 1500;    // the query is evenly thinned to at most this many

// The candidate's points, their kd-tree and each point's information W = C^-1, C the GICP
// regularisation of its neighbourhood's covariance: sigma^2 U diag(flatness, 1, 1) U^T with U
// the neighbourhood's eigenvectors, smallest first (a soft point-to-plane distance).
struct CandidateCloud {
    pcl::PointCloud<pcl::PointXYZ>::Ptr cloud{new pcl::PointCloud<pcl::PointXYZ>};
    pcl::KdTreeFLANN<pcl::PointXYZ> tree;
    std::vector<Eigen::Matrix3d> information;
    // The directions a point's neighbourhood fixes (observability): its normal for a plane, the two
    // across it for a line, every direction for a compact cluster.
    std::vector<Eigen::Matrix3d> constrained;
};

// The directions a neighbourhood with these eigenvalues (ascending) and eigenvectors fixes.
Eigen::Matrix3d ConstrainedDirections(const Eigen::Vector3d &lambda, const Eigen::Matrix3d &U) {
    constexpr double kThin = 0.1;  // an extent below this fraction of the next one is flat
    if (lambda(1) < kThin * lambda(2))  // a line along U.col(2)
        return Eigen::Matrix3d::Identity() - U.col(2) * U.col(2).transpose();
    if (lambda(0) < kThin * lambda(1)) return U.col(0) * U.col(0).transpose();  // a plane
    return Eigen::Matrix3d::Identity();
}

void BuildCandidate(const Eigen::Matrix3Xf &points, const VerificationConfig &config,
                    CandidateCloud &out) {
    out.cloud->points.reserve(points.cols());
    for (Eigen::Index i = 0; i < points.cols(); ++i)
        out.cloud->points.emplace_back(points(0, i), points(1, i), points(2, i));
    out.cloud->width = static_cast<uint32_t>(out.cloud->points.size());
    out.cloud->height = 1;
    out.tree.setInputCloud(out.cloud);
    const double inv_sigma2 = 1.0 / (config.point_sigma_m * config.point_sigma_m);
    const Eigen::Matrix3d isotropic = Eigen::Matrix3d::Identity() * inv_sigma2;
    out.information.assign(points.cols(), isotropic);
    out.constrained.assign(points.cols(), Eigen::Matrix3d::Identity());
    std::vector<int> index(kNeighbours);
    std::vector<float> distance2(kNeighbours);
    for (Eigen::Index i = 0; i < points.cols(); ++i) {
        if (out.tree.nearestKSearch(out.cloud->points[i], kNeighbours, index, distance2) < 5) continue;
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        for (int j : index) mean += points.col(j).cast<double>();
        mean /= static_cast<double>(index.size());
        Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
        for (int j : index) {
            const Eigen::Vector3d d = points.col(j).cast<double>() - mean;
            covariance += d * d.transpose();
        }
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
        const Eigen::Matrix3d &U = eigen.eigenvectors();
        const Eigen::Vector3d weights(1.0 / config.plane_flatness, 1.0, 1.0);
        out.information[i] = U * (weights * inv_sigma2).asDiagonal() * U.transpose();
        out.constrained[i] = ConstrainedDirections(eigen.eigenvalues(), U);
    }
}

struct LinearSystem {
    Matrix6d H = Matrix6d::Zero();
    Vector6d b = Vector6d::Zero();
    Matrix6d H_constrained = Matrix6d::Zero();  // sum J^T P J: the directions the structure fixes
    int correspondences = 0;
    double squared_distance = 0.0;   // sum |r|^2
    double mahalanobis = 0.0;        // sum r^T W r
    std::unordered_set<mapping::VoxelKey, mapping::VoxelKeyHash> cells;
};

// One Gauss-Newton system of the query points at T_candidate_query (the right perturbation:
// T Exp(xi) p = R p + t + R rho - R Hat(p) phi, so J = [R, -R Hat(p)]), Cauchy-weighted.
LinearSystem Linearise(const CandidateCloud &candidate, const std::vector<Eigen::Vector3d> &query,
                       const Eigen::Isometry3d &T, double threshold_m, double cluster_m) {
    LinearSystem system;
    std::vector<int> index(1);
    std::vector<float> distance2(1);
    const Eigen::Matrix3d R = T.rotation();
    for (const Eigen::Vector3d &p : query) {
        const Eigen::Vector3d p_candidate = T * p;
        const pcl::PointXYZ search(static_cast<float>(p_candidate.x()),
                                   static_cast<float>(p_candidate.y()),
                                   static_cast<float>(p_candidate.z()));
        if (candidate.tree.nearestKSearch(search, 1, index, distance2) < 1 ||
            distance2[0] > threshold_m * threshold_m)
            continue;
        const pcl::PointXYZ &q = candidate.cloud->points[index[0]];
        const Eigen::Vector3d q_candidate(q.x, q.y, q.z);
        const Eigen::Vector3d r = p_candidate - q_candidate;
        const Eigen::Matrix3d &W = candidate.information[index[0]];
        const double chi2 = r.dot(W * r);
        const double weight = 1.0 / (1.0 + chi2 / 9.0);  // Cauchy at 3 sigma
        Eigen::Matrix<double, 3, 6> J;
        J.leftCols<3>() = R;
        J.rightCols<3>() = -R * Hat(p);
        system.H += weight * J.transpose() * W * J;
        system.b += weight * J.transpose() * W * r;
        system.H_constrained += J.transpose() * candidate.constrained[index[0]] * J;
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
double HorizontalObservability(const Matrix6d &H, const Eigen::Vector3d &centre, double radius_m) {
    const int axes[3] = {0, 1, 5};
    Eigen::Matrix3d block;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) block(i, j) = H(axes[i], axes[j]);
    // About the points' centre c instead of the anchor (a turn about a far anchor is mostly a
    // shift): dt = dt_c + dyaw (c_y, -c_x), then the yaw in metres at the RMS radius.
    Eigen::Matrix3d about_centre = Eigen::Matrix3d::Identity();
    about_centre(0, 2) = centre.y();
    about_centre(1, 2) = -centre.x();
    const Eigen::Vector3d scale(1.0, 1.0, 1.0 / std::max(radius_m, 1.0));
    block = scale.asDiagonal() * about_centre.transpose() * block * about_centre * scale.asDiagonal();
    const Eigen::Vector3d eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(block).eigenvalues();
    return eigenvalues(2) > 0.0 ? std::max(eigenvalues(0), 0.0) / eigenvalues(2) : 0.0;
}

// The registration's information counted once per cell and scaled by the residuals' variance,
// inverted (regularised) with the floor added, and inverted back.
Matrix6d EdgeInformation(const LinearSystem &system, const VerificationConfig &config) {
    const double per_cell =
        static_cast<double>(system.cells.size()) / std::max(system.correspondences, 1);
    const double variance_scale = std::max(1.0, system.mahalanobis / (3.0 * system.correspondences));
    const Matrix6d H = system.H * per_cell / variance_scale;
    const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(H);
    const double largest = std::max(eigen.eigenvalues().maxCoeff(), 1e-12);
    const Vector6d inverse = eigen.eigenvalues().cwiseMax(largest * 1e-9).cwiseInverse();
    Matrix6d covariance = eigen.eigenvectors() * inverse.asDiagonal() * eigen.eigenvectors().transpose();
    const double t2 = config.floor_sigma_translation_m * config.floor_sigma_translation_m;
    const double r2 = config.floor_sigma_rotation_rad * config.floor_sigma_rotation_rad;
    covariance.diagonal() += (Vector6d() << t2, t2, t2, r2, r2, r2).finished();
    const Matrix6d information = covariance.inverse();
    return 0.5 * (information + information.transpose());
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
    CandidateCloud candidate;
    BuildCandidate(candidate_points, config, candidate);
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
    bool converged = false;
    const int shrink = std::max(1, config.max_iterations / 2);
    for (int iteration = 0; iteration < config.max_iterations; ++iteration) {
        const double alpha = std::min(1.0, static_cast<double>(iteration) / shrink);
        const double threshold =
            config.initial_threshold_m + alpha * (config.final_threshold_m - config.initial_threshold_m);
        const LinearSystem system = Linearise(candidate, query, T, threshold, config.cluster_m);
        result.iterations = iteration + 1;
        if (system.correspondences < 6) break;
        const Vector6d xi = -system.H.ldlt().solve(system.b);
        if (!xi.allFinite()) break;
        T = T * ExpSE3(xi);
        if (alpha >= 1.0 && xi.head<3>().norm() < 1e-3 && xi.tail<3>().norm() < 1e-4) {
            converged = true;
            break;
        }
    }
    result.T_candidate_query = T;
    const LinearSystem final_system =
        Linearise(candidate, query, T, config.final_threshold_m, config.cluster_m);
    result.correspondences = final_system.correspondences;
    result.overlap = static_cast<double>(final_system.correspondences) / static_cast<double>(query.size());
    result.rms_m = final_system.correspondences > 0
                       ? std::sqrt(final_system.squared_distance / final_system.correspondences)
                       : 0.0;
    result.observability = HorizontalObservability(final_system.H_constrained, centre, radius_m);
    if (final_system.correspondences >= 6) result.information = EdgeInformation(final_system, config);
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
