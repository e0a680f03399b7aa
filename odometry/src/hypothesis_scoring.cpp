// RANSAC's hypothesis scoring over structure-of-arrays data (robust_fit.hpp, ScoringSet).
//
// The scoring subset is stored once per scan as contiguous x, y, z, b, gate^2 and 1/gate^2
// arrays, grouped by direction cell and padded to whole vectors with points that are never
// inliers, so that scoring a hypothesis is one branch-free loop per cell over 4-wide vectors
// (GCC vector extensions: one AVX2 register, or two SSE2 registers on the default clone; the
// same lanes and the same sums in either, so the result does not depend on the machine). No FMA:
// the residual is rounded exactly as the scalar r = d . v - b of the refit passes, so that the
// inlier counts (and with them the bail-out decisions) are the same as a scalar loop's.
#include <algorithm>
#include <cmath>

#include "robust_fit.hpp"
#include "simd4.hpp"

namespace dorado::odometry::internal {
namespace {

using simd::Broadcast;
using simd::Load;
using simd::Mask4;
using simd::Sum;
using simd::Vec4;
static_assert(ScoringSet::kLanes == simd::kLanes, "one vector per group of points");

// Writes point `from` of s at row k.
inline void Put(ScoringSet &set, std::size_t k, const DopplerSystem &s, Eigen::Index from) {
    set.x[k] = s.A(from, 0);
    set.y[k] = s.A(from, 1);
    set.z[k] = s.A(from, 2);
    set.b[k] = s.b[from];
    set.gate2[k] = s.gate2[from];
    set.inv_gate2[k] = 1.0 / s.gate2[from];
}

// Writes a padding point at row k: no hypothesis makes it an inlier (gate^2 < 0).
inline void Pad(ScoringSet &set, std::size_t k) {
    set.x[k] = set.y[k] = set.z[k] = set.b[k] = set.inv_gate2[k] = 0.0;
    set.gate2[k] = -1.0;
}

Eigen::Index RoundUp(Eigen::Index n) {
    return (n + ScoringSet::kLanes - 1) / ScoringSet::kLanes * ScoringSet::kLanes;
}

}  // namespace

void ScoringSet::Build(const DopplerSystem &s, Eigen::Index check_points) {
    const Eigen::Index m = s.size();
    check_points = std::min(check_points, m);
    alias_span = s.alias_span;
    // Points per cell, hence each part's offset (a stable counting sort: the shuffled order within
    // a cell).
    const auto cells = static_cast<std::size_t>(s.num_cells);
    order_next.assign(cells, 0);
    for (Eigen::Index i = 0; i < m; ++i) ++order_next[static_cast<std::size_t>(s.cell[i])];
    cell_begin.resize(cells + 1);
    check_end = RoundUp(check_points);
    cell_begin[0] = check_end;
    for (std::size_t c = 0; c < cells; ++c)
        cell_begin[c + 1] = cell_begin[c] + RoundUp(order_next[c]);
    const auto size = static_cast<std::size_t>(cell_begin[cells]);
    for (auto *column : {&x, &y, &z, &b, &gate2, &inv_gate2}) column->resize(size);
    // The bail-out sample: the first points of the shuffled subset, in their order.
    for (Eigen::Index i = 0; i < check_end; ++i) {
        if (i < check_points)
            Put(*this, static_cast<std::size_t>(i), s, i);
        else
            Pad(*this, static_cast<std::size_t>(i));
    }
    // Then every point of the subset, grouped by cell, each cell padded.
    for (std::size_t c = 0; c < cells; ++c) order_next[c] = cell_begin[c];
    for (Eigen::Index i = 0; i < m; ++i)
        Put(*this, static_cast<std::size_t>(order_next[s.cell[i]]++), s, i);
    for (std::size_t c = 0; c < cells; ++c)
        for (auto k = order_next[c]; k < cell_begin[c + 1]; ++k)
            Pad(*this, static_cast<std::size_t>(k));
}

DORADO_SIMD_CLONES int CountInliers(const ScoringSet &set, const double *v) {
    const Vec4 vx = Broadcast(v[0]), vy = Broadcast(v[1]), vz = Broadcast(v[2]);
    Mask4 count = {0, 0, 0, 0};
    for (Eigen::Index i = 0; i < set.check_end; i += ScoringSet::kLanes) {
        const Vec4 r =
            Load(&set.x[i]) * vx + Load(&set.y[i]) * vy + Load(&set.z[i]) * vz - Load(&set.b[i]);
        count -= r * r < Load(&set.gate2[i]);  // true is -1
    }
    return static_cast<int>(Sum(count));
}

DORADO_SIMD_CLONES int ScoreCells(const ScoringSet &set, const double *v, double *cell_quality,
                                  int *cell_count) {
    const Vec4 vx = Broadcast(v[0]), vy = Broadcast(v[1]), vz = Broadcast(v[2]),
               one = Broadcast(1.0);
    const auto cells = static_cast<int>(set.cell_begin.size()) - 1;
    int total = 0;
    for (int c = 0; c < cells; ++c) {
        Vec4 quality = {0.0, 0.0, 0.0, 0.0};
        Mask4 count = {0, 0, 0, 0};
        for (Eigen::Index i = set.cell_begin[c]; i < set.cell_begin[c + 1];
             i += ScoringSet::kLanes) {
            const Vec4 r = Load(&set.x[i]) * vx + Load(&set.y[i]) * vy + Load(&set.z[i]) * vz -
                           Load(&set.b[i]);
            const Vec4 r2 = r * r;
            const Mask4 inlier = r2 < Load(&set.gate2[i]);
            // MSAC quality 1 - r^2 / gate^2 of the inliers, 0 for the others.
            quality += simd::Select(inlier, one - r2 * Load(&set.inv_gate2[i]));
            count -= inlier;
        }
        cell_quality[c] = Sum(quality);
        cell_count[c] = static_cast<int>(Sum(count));
        total += cell_count[c];
    }
    return total;
}

int ScoreCellsAliased(const ScoringSet &set, const double *v, double *cell_quality,
                      int *cell_count) {
    const double span = set.alias_span;  // the wrap of each Doppler closest to the hypothesis
    const auto cells = static_cast<int>(set.cell_begin.size()) - 1;
    int total = 0;
    for (int c = 0; c < cells; ++c) {
        cell_quality[c] = 0.0;
        cell_count[c] = 0;
        for (Eigen::Index i = set.cell_begin[c]; i < set.cell_begin[c + 1]; ++i) {
            double r = set.x[i] * v[0] + set.y[i] * v[1] + set.z[i] * v[2] - set.b[i];
            r -= span * std::round(r / span);
            const double r2 = r * r;
            if (!(r2 < set.gate2[i])) continue;
            cell_quality[c] += 1.0 - r2 * set.inv_gate2[i];
            ++cell_count[c];
        }
        total += cell_count[c];
    }
    return total;
}

int CountInliersAliased(const ScoringSet &set, const double *v) {
    const double span = set.alias_span;
    int count = 0;
    for (Eigen::Index i = 0; i < set.check_end; ++i) {
        double r = set.x[i] * v[0] + set.y[i] * v[1] + set.z[i] * v[2] - set.b[i];
        r -= span * std::round(r / span);
        count += r * r < set.gate2[i];
    }
    return count;
}

}  // namespace dorado::odometry::internal
