#pragma once
// Internal to dorado_odometry: the linear system of eq. (1)-(2) and the robust solvers on it.

#include <Eigen/Core>
#include <array>
#include <optional>
#include <random>
#include <vector>

#include "dorado/odometry/ego_velocity.hpp"

namespace dorado::odometry::internal {

/// Eq. (1) for every point that passed the pre-filters: row i of A is d_i^T and b_i = -doppler_i,
/// so that A v_radar = b for a static scene.
struct DopplerSystem {
    Eigen::Matrix<double, Eigen::Dynamic, 3> A;
    Eigen::VectorXd b;
    Eigen::VectorXd w;      ///< weights of eq. (2), largest = 1
    Eigen::VectorXd gate2;  ///< squared inlier gate per point [m^2/s^2]
    Eigen::VectorXi cell;   ///< direction cell of each point, for spread-aware scoring
    int num_cells = 1;
    /// 2 * doppler_unambiguous_mps: b_i is known modulo this (0 = no aliasing).
    double alias_span = 0.0;

    [[nodiscard]] Eigen::Index size() const { return b.size(); }
    void Resize(Eigen::Index n);
};

/// The normal equations of eq. (2), A^T W A (upper triangle: xx xy xz yy yz zz) and A^T W b.
struct NormalEquations {
    std::array<double, 6> gram{};
    std::array<double, 3> rhs{};
    void Add(const NormalEquations &other);
    [[nodiscard]] Eigen::Matrix3d AtWA() const;
};

/// Per-point buffers of one system size. RANSAC keeps one set for its scoring subset and uses
/// the workspace's own for all points, so that neither is reallocated when the other is used
/// (alternating sizes made glibc return and re-fault the pages at every scan: 1.6 -> 0.3 ms per
/// 5 000-point scan).
struct Scratch {
    Eigen::VectorXd residual, mask, weighted;
};

/// RANSAC's scoring subset as structure-of-arrays (hypothesis_scoring.cpp): first the bail-out
/// sample (the first points of the shuffled subset, in order), then every point of the subset
/// grouped by direction cell; each part padded to whole vectors of kLanes with points that no
/// hypothesis makes inliers (gate2 < 0). Rebuilt per scan into the same buffers.
struct ScoringSet {
    static constexpr int kLanes = 4;
    std::vector<double> x, y, z, b, gate2, inv_gate2;
    Eigen::Index check_end = 0;            ///< the bail-out sample is [0, check_end)
    std::vector<Eigen::Index> cell_begin;  ///< cell c is [cell_begin[c], cell_begin[c + 1])
    double alias_span = 0.0;
    std::vector<Eigen::Index> order_next;  ///< Build's counting sort

    /// From the shuffled subset `s` with its cells assigned; the first `check_points` of `s` are
    /// the bail-out sample.
    void Build(const DopplerSystem &s, Eigen::Index check_points);
};

/// Inliers of hypothesis v (3 doubles) in the bail-out sample.
int CountInliers(const ScoringSet &set, const double *v);
/// Per cell c: the MSAC quality sum of (1 - r^2 / gate^2) over v's inliers in `cell_quality[c]`,
/// their count in `cell_count[c]`; returns the total count.
int ScoreCells(const ScoringSet &set, const double *v, double *cell_quality, int *cell_count);
/// The same two with aliased Doppler: each residual wrapped by set.alias_span first (scalar).
int CountInliersAliased(const ScoringSet &set, const double *v);
int ScoreCellsAliased(const ScoringSet &set, const double *v, double *cell_quality,
                      int *cell_count);

/// Buffers reused from scan to scan so that the RANSAC loop never allocates.
struct Workspace {
    DopplerSystem system;                     ///< all used points
    DopplerSystem subset;                     ///< the random subset RANSAC scores hypotheses on
    std::vector<Eigen::Index> used_to_input;  ///< row of `system` -> index in the scan
    std::vector<double> keep;     ///< the pre-filter's verdict per scan point (1 = kept)
    Eigen::VectorXd zeros, nans;  ///< stand-ins for a scan's missing columns
    std::vector<Eigen::Index> shuffle;
    Eigen::VectorXd residual, mask, weighted, sort_buffer;
    Eigen::ArrayXXd direction_noise;  ///< FitWithDirectionNoise's per-point terms (n x 9)
    Eigen::ArrayXd cell_score;
    Eigen::ArrayXi cell_inliers, cell_total, best_cell_inliers;
    Scratch subset_scratch;  ///< RANSAC's buffers on `subset`
    ScoringSet scoring;      ///< `subset` laid out for scoring
    /// Normal equations of eq. (2) on `mask`, left by Ransac (its last classification pass).
    NormalEquations mask_equations;
    std::mt19937_64 rng;
};

/// One pass: weighted_i = w_i * mask_i and the normal equations with W = diag(weighted).
NormalEquations Accumulate(const DopplerSystem &system, const Eigen::VectorXd &mask,
                           Eigen::VectorXd &weighted);

/// v = (A^T W A)^-1 A^T W b; false when A^T W A is singular (a pivot below 1e-12 of the largest).
bool SolveNormalEquations(const NormalEquations &ne, Eigen::Vector3d &v);

/// One pass for the covariance: rWr = sum weighted_i r_i^2 (returned in `rWr`) and, as the
/// gram of the result, sum (weighted_i r_i)^2 d_i d_i^T (the sandwich's meat).
NormalEquations ResidualMoments(const DopplerSystem &system, const Eigen::VectorXd &weighted,
                                const Eigen::VectorXd &residual, double &rWr);

/// Weighted least squares (eq. 2) on the rows with mask_i = 1: v = (A^T W A)^-1 A^T W b.
/// `AtWA` receives A^T W A. False when A^T W A is singular.
bool SolveWeighted(const DopplerSystem &system, const Eigen::VectorXd &mask, Workspace &ws,
                   Eigen::Vector3d &v, Eigen::Matrix3d &AtWA);

/// With aliasing (alias_span > 0), moves each b_i by a multiple of alias_span to the value
/// closest to A_i v (the wrap that fits the hypothesis). No-op otherwise.
void Unwrap(DopplerSystem &system, const Eigen::Vector3d &v);

/// Unwraps b against v, sets ws.residual = A v - b and mask_i = 1 where residual_i^2 < gate2_i;
/// returns the count.
int ClassifyInliers(DopplerSystem &system, const Eigen::Vector3d &v, Workspace &ws,
                    Eigen::VectorXd &mask);

/// ClassifyInliers into (residual, mask) and, in the same pass, weighted = w_i * mask_i and the
/// normal equations of eq. (2) on the new mask: what SolveWeighted on it would sum. Returns the
/// count.
int ClassifyAndAccumulate(DopplerSystem &system, const Eigen::Vector3d &v,
                          Eigen::VectorXd &residual, Eigen::VectorXd &mask,
                          Eigen::VectorXd &weighted, NormalEquations &equations);

/// x with M x = r, bit for bit as Eigen's PartialPivLU<Matrix3d>(M).solve(r) gives it (the same
/// pivots, operations and roundings) without its bookkeeping (the L1 norm, the permutation).
[[nodiscard]] Eigen::Vector3d SolvePartialPivot3(Eigen::Matrix3d M, Eigen::Vector3d r);

/// The 3-point model with aliased Doppler (alias_span > 0): the best of the 27 wraps of the
/// sample (alias_hypotheses.cpp). False for a degenerate sample or no wrap below max_speed_mps.
bool SolveMinimalAliased(const DopplerSystem &s, Eigen::Index i, Eigen::Index j, Eigen::Index k,
                         double max_speed_mps, Eigen::Vector3d &v);

/// The final fit with direction noise (config.sensor): per-point total variance
/// sigma_i^2 + v^T C_i v for the gates, and the bias-compensated (errors-in-variables)
/// estimating equation sum w_i (d_i b_i - (d_i d_i^T - C_i) S_i^-1 v) = 0, refit until the inlier
/// set settles, starting from v (RANSAC's). Sets ws.mask, ws.residual, ws.weighted; `AtWA` gets
/// sum w_i d_i d_i^T on the inliers, `covariance` the sandwich covariance. False when singular.
bool FitWithDirectionNoise(const EgoVelocityConfig &config, Workspace &ws, Eigen::Vector3d &v,
                           Eigen::Matrix3d &AtWA, Eigen::Matrix3d &covariance);

/// RANSAC with 3-point samples, spread-aware MSAC scoring on ws.subset, local refits, then
/// refit-and-regate on all points. Leaves the inlier mask in ws.mask. False when no
/// non-degenerate sample was found.
/// With `ball`, hypotheses (and their local refits) outside it are not scored; false when no
/// hypothesis inside was found.
bool Ransac(const EgoVelocityConfig &config, Workspace &ws, Eigen::Vector3d &v, int &iterations,
            const std::optional<VelocityPrediction> &ball = std::nullopt);

/// The paper's reference trimmed IRLS: start from every point, refit on the points its
/// threshold keeps, until the velocity stops moving. Leaves the inlier mask in ws.mask.
bool TrimmedIrls(const EgoVelocityConfig &config, Workspace &ws, Eigen::Vector3d &v,
                 int &iterations);

}  // namespace dorado::odometry::internal
