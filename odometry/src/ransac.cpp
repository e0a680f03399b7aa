// RANSAC for the sensor velocity (paper section III-A), with the three changes that real radar
// data needs: the winning model is refit on its inliers (LO-RANSAC), hypotheses are scored by the
// spread of their inliers over directions (a crowd moving together cannot outvote the static
// world that surrounds the sensor), and the inlier gate follows each point's Doppler noise.
#include <Eigen/LU>  // determinant()
#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "robust_fit.hpp"

namespace dorado::odometry::internal {
namespace {

// |det| of three unit directions = volume of their parallelepiped; below this the three
// equations of eq. (1) are nearly dependent and the minimal solution is noise.
constexpr double kMinSampleVolume = 1e-4;

// The minimal model: eq. (1) for three points solved exactly.
bool SolveMinimal(const DopplerSystem &s, Eigen::Index i, Eigen::Index j, Eigen::Index k,
                  Eigen::Vector3d &v) {
    Eigen::Matrix3d M;
    M.row(0) = s.A.row(i);
    M.row(1) = s.A.row(j);
    M.row(2) = s.A.row(k);
    if (std::abs(M.determinant()) < kMinSampleVolume) return false;
    v = SolvePartialPivot3(M, Eigen::Vector3d(s.b[i], s.b[j], s.b[k]));
    return v.allFinite();
}

// A cheap angle proxy, monotonic in atan2(y, x), in [0, 4), wrapping at the -X axis of the
// rotated frame (see AssignCells). Used only to bin directions.
double PseudoAngle(double x, double y) {
    const double ax = std::abs(x), ay = std::abs(y);
    if (ax + ay == 0.0) return 2.0;
    // Diamond angle of (-x, -y): 0 at -X, 2 at +X.
    const double px = -x, py = -y;
    if (py >= 0) return px >= 0 ? py / (px + py) : 1.0 - px / (-px + py);
    return px < 0 ? 2.0 - py / (-px - py) : 3.0 + px / (px - py);
}

// Direction cells for the spread-aware RANSAC score: an azimuth x elevation grid over the
// extent of this scan's directions, azimuth measured from the mean horizontal direction.
void AssignCells(const EgoVelocityConfig &config, DopplerSystem &s, Eigen::VectorXd &azimuth) {
    const Eigen::Index n = s.size();
    s.num_cells = config.score_cells_azimuth * config.score_cells_elevation;
    if (s.num_cells == 1 || n == 0) {
        s.cell.setZero();
        return;
    }
    Eigen::Vector2d mean(s.A.col(0).sum(), s.A.col(1).sum());
    mean = mean.norm() > 1e-9 * n ? Eigen::Vector2d(mean.normalized()) : Eigen::Vector2d(1, 0);
    const double el_min = s.A.col(2).minCoeff(), el_max = s.A.col(2).maxCoeff();
    azimuth.resize(n);
    for (Eigen::Index i = 0; i < n; ++i)
        azimuth[i] = PseudoAngle(mean.x() * s.A(i, 0) + mean.y() * s.A(i, 1),
                                 -mean.y() * s.A(i, 0) + mean.x() * s.A(i, 1));
    const double az_min = azimuth.minCoeff(), az_max = azimuth.maxCoeff();
    const double az_scale = config.score_cells_azimuth / std::max(az_max - az_min, 1e-9);
    const double el_scale = config.score_cells_elevation / std::max(el_max - el_min, 1e-9);
    for (Eigen::Index i = 0; i < n; ++i) {
        const int ca = std::min(config.score_cells_azimuth - 1,
                                static_cast<int>((azimuth[i] - az_min) * az_scale));
        const int ce = std::min(config.score_cells_elevation - 1,
                                static_cast<int>((s.A(i, 2) - el_min) * el_scale));
        s.cell[i] = ce * config.score_cells_azimuth + ca;
    }
}

// Spread-aware MSAC score: each inlier contributes its quality 1 - r^2/gate^2 to its direction
// cell, and a cell contributes sqrt(its sum). Returns the score; `inliers` gets the count and
// ws.cell_inliers the inliers per cell. Vectorised over ws.scoring (hypothesis_scoring.cpp).
// Bail-out (Capel 2005): a hypothesis with fewer than `min_check_inliers` inliers among the
// bail-out sample (the first points of the shuffled subset, a random sample) is dropped (returns
// -1) without scoring the rest; bail_out = false scores everything.
double Score(const Eigen::Vector3d &v, Workspace &ws, int &inliers, bool bail_out = false,
             int min_check_inliers = 0) {
    const ScoringSet &set = ws.scoring;
    const bool aliased = set.alias_span > 0.0;
    inliers = 0;
    if (bail_out && set.check_end > 0) {
        const int check =
            aliased ? CountInliersAliased(set, v.data()) : CountInliers(set, v.data());
        if (check < min_check_inliers) return -1.0;
    }
    inliers = aliased
                  ? ScoreCellsAliased(set, v.data(), ws.cell_score.data(), ws.cell_inliers.data())
                  : ScoreCells(set, v.data(), ws.cell_score.data(), ws.cell_inliers.data());
    return ws.cell_score.sqrt().sum();
}

// Copies a random subset of `count` rows of `from` into `to` (partial Fisher-Yates).
void DrawSubset(const DopplerSystem &from, Eigen::Index count, Workspace &ws, DopplerSystem &to) {
    const Eigen::Index n = from.size();
    ws.shuffle.resize(n);
    std::iota(ws.shuffle.begin(), ws.shuffle.end(), 0);
    to.Resize(count);
    to.alias_span = from.alias_span;
    for (Eigen::Index k = 0; k < count; ++k) {
        std::uniform_int_distribution<Eigen::Index> pick(k, n - 1);
        std::swap(ws.shuffle[k], ws.shuffle[pick(ws.rng)]);
        const Eigen::Index i = ws.shuffle[k];
        to.A.row(k) = from.A.row(i);
        to.b[k] = from.b[i];
        to.w[k] = from.w[i];
        to.gate2[k] = from.gate2[i];
    }
}

// Fraction of the occupied direction cells in which the last scored hypothesis explains the
// majority of the points. A static world scores high; a crowd moving together (a bus) wins only
// its own few cells.
double CellCoverage(const Workspace &ws, const Eigen::ArrayXi &cell_inliers) {
    int occupied = 0, won = 0;
    for (Eigen::Index c = 0; c < ws.cell_total.size(); ++c) {
        if (ws.cell_total[c] == 0) continue;
        ++occupied;
        won += 2 * cell_inliers[c] > ws.cell_total[c];
    }
    return occupied ? static_cast<double>(won) / occupied : 0.0;
}

// Iterations needed to draw one all-inlier sample with the given probability.
int RequiredIterations(double inlier_ratio, double success_probability) {
    const double p_good = inlier_ratio * inlier_ratio * inlier_ratio;
    if (p_good >= 1.0) return 1;
    if (p_good <= 0.0) return std::numeric_limits<int>::max();
    const double k = std::log(1.0 - success_probability) / std::log(1.0 - p_good);
    return k > 1e9 ? std::numeric_limits<int>::max() : static_cast<int>(std::ceil(k));
}

}  // namespace

Eigen::Vector3d SolvePartialPivot3(Eigen::Matrix3d M, Eigen::Vector3d r) {
    // Gaussian elimination with partial pivoting in Eigen's order (PartialPivLU's unblocked_lu:
    // the first largest |pivot|, the column divided by it, the rank-1 update; the last pivot
    // taken as it is), the row swaps applied to r as they happen (P r).
    for (int k = 0; k < 2; ++k) {
        int pivot = k;
        for (int i = k + 1; i < 3; ++i)
            if (std::abs(M(i, k)) > std::abs(M(pivot, k))) pivot = i;
        if (M(pivot, k) != 0.0) {
            if (pivot != k) {
                M.row(k).swap(M.row(pivot));
                std::swap(r[k], r[pivot]);
            }
            for (int i = k + 1; i < 3; ++i) M(i, k) /= M(k, k);
        }
        for (int j = k + 1; j < 3; ++j)
            for (int i = k + 1; i < 3; ++i) M(i, j) -= M(i, k) * M(k, j);
    }
    // L y = P r (unit lower), then U x = y, each row's sum in Eigen's order.
    r[1] -= M(1, 0) * r[0];
    r[2] -= M(2, 0) * r[0] + M(2, 1) * r[1];
    r[2] /= M(2, 2);
    r[1] -= M(1, 2) * r[2];
    r[1] /= M(1, 1);
    r[0] -= M(0, 1) * r[1] + M(0, 2) * r[2];
    r[0] /= M(0, 0);
    return r;
}

bool Ransac(const EgoVelocityConfig &config, Workspace &ws, Eigen::Vector3d &v, int &iterations,
            const std::optional<VelocityPrediction> &ball) {
    const auto outside = [&ball](const Eigen::Vector3d &hypothesis) {
        return ball && (hypothesis - ball->v_radar_mps).norm() > ball->radius_mps;
    };
    DopplerSystem &all = ws.system;  // not const: ClassifyInliers unwraps aliased Doppler
    const Eigen::Index n = all.size();
    // Always a shuffled copy, so that its first points are a random sample for the bail-out.
    const Eigen::Index subset_size =
        config.ransac_score_points > 0 ? std::min<Eigen::Index>(n, config.ransac_score_points) : n;
    DrawSubset(all, subset_size, ws, ws.subset);
    DopplerSystem &s = ws.subset;
    Scratch &scratch = ws.subset_scratch;
    AssignCells(config, s, ws.sort_buffer);
    const Eigen::Index m = s.size();
    ws.cell_score.resize(s.num_cells);
    ws.cell_inliers.resize(s.num_cells);
    ws.cell_total.setZero(s.num_cells);
    for (Eigen::Index i = 0; i < m; ++i) ++ws.cell_total[s.cell[i]];
    const Eigen::Index check = config.ransac_bailout_points < m ? config.ransac_bailout_points : 0;
    ws.scoring.Build(s, check);

    std::uniform_int_distribution<Eigen::Index> pick(0, m - 1);
    double best_score = -1.0;
    int best_count = 0;
    Eigen::Vector3d best_v = Eigen::Vector3d::Zero();
    // Held in a ball, most samples fall outside it: search until one inside is found (the
    // stopping rule then applies as usual).
    int needed = ball ? config.ransac_max_iterations : config.ransac_min_iterations;
    Eigen::Vector3d candidate;
    Eigen::ArrayXi &best_cells = ws.best_cell_inliers;  // the best hypothesis' inliers per cell
    iterations = 0;
    // Hard cap: at most ransac_max_iterations hypotheses; when the stopping rule has not been met
    // by then, the best hypothesis so far is refit below (the fallback), as if it had.
    for (; iterations < std::max(needed, config.ransac_min_iterations) &&
           iterations < config.ransac_max_iterations;
         ++iterations) {
        const Eigen::Index i = pick(ws.rng), j = pick(ws.rng), k = pick(ws.rng);
        if (i == j || j == k || i == k) continue;
        if (!(s.alias_span > 0.0 ? SolveMinimalAliased(s, i, j, k, config.max_speed_mps, candidate)
                                 : SolveMinimal(s, i, j, k, candidate)))
            continue;
        if (outside(candidate)) continue;
        // Expected inliers among the first `check` points if this hypothesis were as good as the
        // best one, times the bail-out fraction.
        const int min_check = static_cast<int>(config.ransac_bailout_fraction * best_count *
                                               static_cast<double>(check) / static_cast<double>(m));
        int count = 0;
        double score = Score(candidate, ws, count, check > 0, min_check);
        if (score <= best_score) continue;
        // Local optimisation: refit on this hypothesis' inliers of the subset (eq. 2), keep the
        // refit when it scores better. Cheap, and turns the noisy 3-point model into a good one.
        best_cells = ws.cell_inliers;
        for (int round = 0; round < 2; ++round) {
            NormalEquations equations;
            ClassifyAndAccumulate(s, candidate, scratch.residual, scratch.mask, scratch.weighted,
                                  equations);
            Eigen::Vector3d refit;
            if (!SolveNormalEquations(equations, refit) || outside(refit)) break;
            int refit_count = 0;
            const double refit_score = Score(refit, ws, refit_count);
            if (refit_score <= score) break;
            candidate = refit;
            score = refit_score;
            count = refit_count;
            best_cells = ws.cell_inliers;
        }
        best_score = score;
        best_v = candidate;
        // Stopping rule: the usual one on the inlier ratio, discounted by the cell coverage, so
        // that a compact crowd holding most points does not stop the search before an
        // all-static sample is drawn (the static world then wins on score).
        best_count = count;
        const double ratio = static_cast<double>(count) / static_cast<double>(m);
        needed = RequiredIterations(ratio * CellCoverage(ws, best_cells),
                                    config.ransac_success_probability);
    }
    if (best_score < 0.0) return false;

    // Refit on the inliers among all points, re-gate, until the inlier set settles.
    // One pass per round: classify against v and sum the next refit's normal equations.
    v = best_v;
    NormalEquations &equations = ws.mask_equations;
    int previous = ClassifyAndAccumulate(all, v, ws.residual, ws.mask, ws.weighted, equations);
    for (int round = 0; round < config.refit_iterations; ++round) {
        Eigen::Vector3d refit;
        if (!SolveNormalEquations(equations, refit)) break;
        v = refit;
        const int count =
            ClassifyAndAccumulate(all, v, ws.residual, ws.mask, ws.weighted, equations);
        if (count == previous) break;
        previous = count;
    }
    return true;
}

}  // namespace dorado::odometry::internal
