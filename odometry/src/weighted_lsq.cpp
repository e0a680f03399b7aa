// Weighted least squares of eq. (2) on a masked subset of the Doppler system.
//
// Every per-point pass here is one loop over the three direction columns that does all of its
// sums at once, so that a refit reads each point once instead of once per matrix entry (12
// passes before): two points at a time (Eigen's 2-lane packets: SSE2 without -march flags), and
// four at a time (simd4.hpp) for the two passes of every RANSAC scan (classification with the
// normal equations, and the covariance's residual moments).
#include <Eigen/Cholesky>
#include <cmath>

#include "robust_fit.hpp"
#include "simd4.hpp"

namespace dorado::odometry::internal {

void DopplerSystem::Resize(Eigen::Index n) {
    A.resize(n, 3);
    b.resize(n);
    w.resize(n);
    gate2.resize(n);
    cell.resize(n);
}

void NormalEquations::Add(const NormalEquations &o) {
    for (int k = 0; k < 6; ++k) gram[k] += o.gram[k];
    for (int k = 0; k < 3; ++k) rhs[k] += o.rhs[k];
}

Eigen::Matrix3d NormalEquations::AtWA() const {
    Eigen::Matrix3d H;
    H << gram[0], gram[1], gram[2], gram[1], gram[3], gram[4], gram[2], gram[4], gram[5];
    return H;
}

namespace {

using Pair = Eigen::Array2d;

Pair Load(const double *p) {
    return Eigen::Map<const Pair>(p);
}

// Sums of sum_i c_i d_i d_i^T (upper triangle) and sum_i c_i y_i d_i over two lanes.
struct PairSums {
    Pair xx = Pair::Zero(), xy = Pair::Zero(), xz = Pair::Zero(), yy = Pair::Zero(),
         yz = Pair::Zero(), zz = Pair::Zero(), xr = Pair::Zero(), yr = Pair::Zero(),
         zr = Pair::Zero();
    void Add(const Pair &c, const Pair &x, const Pair &y, const Pair &z, const Pair &rhs) {
        const Pair cx = c * x, cy = c * y, cz = c * z;
        xx += cx * x;
        xy += cx * y;
        xz += cx * z;
        yy += cy * y;
        yz += cy * z;
        zz += cz * z;
        xr += cx * rhs;
        yr += cy * rhs;
        zr += cz * rhs;
    }
    void Add(double c, double x, double y, double z, double rhs) {
        Add(Pair(c, 0.0), Pair(x, 0.0), Pair(y, 0.0), Pair(z, 0.0), Pair(rhs, 0.0));
    }
    [[nodiscard]] NormalEquations Total() const {
        NormalEquations ne;
        ne.gram = {xx.sum(), xy.sum(), xz.sum(), yy.sum(), yz.sum(), zz.sum()};
        ne.rhs = {xr.sum(), yr.sum(), zr.sum()};
        return ne;
    }
};

}  // namespace

namespace {

using simd::Broadcast;
using simd::Mask4;
using simd::Store;
using simd::Sum;
using simd::Vec4;

// The 4-lane counterpart of PairSums.
struct Vec4Sums {
    Vec4 xx{}, xy{}, xz{}, yy{}, yz{}, zz{}, xr{}, yr{}, zr{};
    void Add(Vec4 c, Vec4 x, Vec4 y, Vec4 z, Vec4 rhs) {
        const Vec4 cx = c * x, cy = c * y, cz = c * z;
        xx += cx * x;
        xy += cx * y;
        xz += cx * z;
        yy += cy * y;
        yz += cy * z;
        zz += cz * z;
        xr += cx * rhs;
        yr += cy * rhs;
        zr += cz * rhs;
    }
    // The lanes' totals plus a scalar tail's sums.
    [[nodiscard]] NormalEquations Total(const NormalEquations &tail) const {
        NormalEquations ne;
        ne.gram = {Sum(xx) + tail.gram[0], Sum(xy) + tail.gram[1], Sum(xz) + tail.gram[2],
                   Sum(yy) + tail.gram[3], Sum(yz) + tail.gram[4], Sum(zz) + tail.gram[5]};
        ne.rhs = {Sum(xr) + tail.rhs[0], Sum(yr) + tail.rhs[1], Sum(zr) + tail.rhs[2]};
        return ne;
    }
};

void AddPoint(NormalEquations &ne, double c, double x, double y, double z, double rhs) {
    const double cx = c * x, cy = c * y, cz = c * z;
    ne.gram[0] += cx * x;
    ne.gram[1] += cx * y;
    ne.gram[2] += cx * z;
    ne.gram[3] += cy * y;
    ne.gram[4] += cy * z;
    ne.gram[5] += cz * z;
    ne.rhs[0] += cx * rhs;
    ne.rhs[1] += cy * rhs;
    ne.rhs[2] += cz * rhs;
}

struct PointColumns {
    const double *x, *y, *z, *b, *w, *gate2;
};

// One pass of ClassifyAndAccumulate: r = A v - b, mask = r^2 < gate^2, weighted = w * mask and
// the normal equations of eq. (2) on the mask.
DORADO_SIMD_CLONES int ClassifyAndAccumulateKernel(Eigen::Index n, const PointColumns &p,
                                                   const double *v, double *r, double *m,
                                                   double *wm, NormalEquations &equations) {
    const Vec4 vx = Broadcast(v[0]), vy = Broadcast(v[1]), vz = Broadcast(v[2]),
               one = Broadcast(1.0);
    Mask4 count{};
    Vec4Sums sums;
    Eigen::Index i = 0;
    for (; i + simd::kLanes <= n; i += simd::kLanes) {
        const Vec4 x = simd::Load(p.x + i), y = simd::Load(p.y + i), z = simd::Load(p.z + i),
                   bi = simd::Load(p.b + i);
        const Vec4 ri = x * vx + y * vy + z * vz - bi;
        const Mask4 inlier = ri * ri < simd::Load(p.gate2 + i);
        const Vec4 c = simd::Select(inlier, simd::Load(p.w + i));
        Store(r + i, ri);
        Store(m + i, simd::Select(inlier, one));
        Store(wm + i, c);
        count -= inlier;  // true is -1
        sums.Add(c, x, y, z, bi);
    }
    auto total = static_cast<int>(Sum(count));
    NormalEquations tail;
    for (; i < n; ++i) {
        r[i] = p.x[i] * v[0] + p.y[i] * v[1] + p.z[i] * v[2] - p.b[i];
        m[i] = r[i] * r[i] < p.gate2[i] ? 1.0 : 0.0;
        wm[i] = p.w[i] * m[i];
        total += m[i] > 0.0;
        AddPoint(tail, wm[i], p.x[i], p.y[i], p.z[i], p.b[i]);
    }
    equations = sums.Total(tail);
    return total;
}

// One pass of ResidualMoments.
DORADO_SIMD_CLONES NormalEquations ResidualMomentsKernel(Eigen::Index n, const double *ax,
                                                         const double *ay, const double *az,
                                                         const double *wm, const double *r,
                                                         double &rWr) {
    Vec4Sums sums;
    Vec4 quadratic{};
    const Vec4 zero{};
    Eigen::Index i = 0;
    for (; i + simd::kLanes <= n; i += simd::kLanes) {
        const Vec4 wr = simd::Load(wm + i) * simd::Load(r + i);
        quadratic += wr * simd::Load(r + i);
        sums.Add(wr * wr, simd::Load(ax + i), simd::Load(ay + i), simd::Load(az + i), zero);
    }
    NormalEquations tail;
    double tail_quadratic = 0.0;
    for (; i < n; ++i) {
        const double wr = wm[i] * r[i];
        tail_quadratic += wr * r[i];
        AddPoint(tail, wr * wr, ax[i], ay[i], az[i], 0.0);
    }
    rWr = Sum(quadratic) + tail_quadratic;
    return sums.Total(tail);
}

}  // namespace

NormalEquations Accumulate(const DopplerSystem &system, const Eigen::VectorXd &mask,
                           Eigen::VectorXd &weighted) {
    const Eigen::Index n = system.size();
    weighted.resize(n);
    const double *ax = system.A.col(0).data(), *ay = system.A.col(1).data(),
                 *az = system.A.col(2).data(), *b = system.b.data(), *w = system.w.data(),
                 *m = mask.data();
    double *wm = weighted.data();
    PairSums sums;
    Eigen::Index i = 0;
    for (; i + 2 <= n; i += 2) {
        // eq. (2): W = diag(w_i * mask_i).
        const Pair c = Load(w + i) * Load(m + i);
        Eigen::Map<Pair>(wm + i) = c;
        sums.Add(c, Load(ax + i), Load(ay + i), Load(az + i), Load(b + i));
    }
    for (; i < n; ++i) {
        wm[i] = w[i] * m[i];
        sums.Add(wm[i], ax[i], ay[i], az[i], b[i]);
    }
    return sums.Total();
}

bool SolveNormalEquations(const NormalEquations &ne, Eigen::Vector3d &v) {
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(ne.AtWA());
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return false;
    // A pivot of ~0 means the weighted directions span less than 3-D.
    const double max_pivot = ldlt.vectorD().maxCoeff();
    if (!(ldlt.vectorD().minCoeff() > 1e-12 * max_pivot)) return false;
    v = ldlt.solve(Eigen::Vector3d(ne.rhs[0], ne.rhs[1], ne.rhs[2]));
    return v.allFinite();
}

namespace {

bool Solve(const DopplerSystem &system, const Eigen::VectorXd &mask, Eigen::VectorXd &weighted,
           Eigen::Vector3d &v, Eigen::Matrix3d &AtWA) {
    // eq. (2): v = (A^T W A)^-1 (A^T W b), W = diag(w_i * mask_i).
    const NormalEquations ne = Accumulate(system, mask, weighted);
    AtWA = ne.AtWA();
    return SolveNormalEquations(ne, v);
}

int Classify(const DopplerSystem &system, const Eigen::Vector3d &v, Eigen::VectorXd &residual,
             Eigen::VectorXd &mask) {
    const Eigen::Index n = system.size();
    residual.resize(n);
    mask.resize(n);
    const double *ax = system.A.col(0).data(), *ay = system.A.col(1).data(),
                 *az = system.A.col(2).data(), *b = system.b.data(), *g2 = system.gate2.data();
    double *r = residual.data(), *m = mask.data();
    const Pair vx = Pair::Constant(v.x()), vy = Pair::Constant(v.y()), vz = Pair::Constant(v.z());
    Pair count = Pair::Zero();
    Eigen::Index i = 0;
    for (; i + 2 <= n; i += 2) {
        const Pair ri = Load(ax + i) * vx + Load(ay + i) * vy + Load(az + i) * vz - Load(b + i);
        const Pair inlier = (ri.square() < Load(g2 + i)).cast<double>();
        Eigen::Map<Pair>(r + i) = ri;
        Eigen::Map<Pair>(m + i) = inlier;
        count += inlier;
    }
    double total = count.sum();
    for (; i < n; ++i) {
        r[i] = ax[i] * v.x() + ay[i] * v.y() + az[i] * v.z() - b[i];
        m[i] = r[i] * r[i] < g2[i] ? 1.0 : 0.0;
        total += m[i];
    }
    return static_cast<int>(total);
}

}  // namespace

NormalEquations ResidualMoments(const DopplerSystem &system, const Eigen::VectorXd &weighted,
                                const Eigen::VectorXd &residual, double &rWr) {
    return ResidualMomentsKernel(system.size(), system.A.col(0).data(), system.A.col(1).data(),
                                 system.A.col(2).data(), weighted.data(), residual.data(), rWr);
}

void Unwrap(DopplerSystem &system, const Eigen::Vector3d &v) {
    const double span = system.alias_span;
    if (!(span > 0.0)) return;
    const Eigen::Index n = system.size();
    for (Eigen::Index i = 0; i < n; ++i)
        system.b[i] += span * std::round((system.A.row(i).dot(v) - system.b[i]) / span);
}

bool SolveWeighted(const DopplerSystem &system, const Eigen::VectorXd &mask, Workspace &ws,
                   Eigen::Vector3d &v, Eigen::Matrix3d &AtWA) {
    return Solve(system, mask, ws.weighted, v, AtWA);
}

int ClassifyInliers(DopplerSystem &system, const Eigen::Vector3d &v, Workspace &ws,
                    Eigen::VectorXd &mask) {
    Unwrap(system, v);
    return Classify(system, v, ws.residual, mask);
}

int ClassifyAndAccumulate(DopplerSystem &system, const Eigen::Vector3d &v,
                          Eigen::VectorXd &residual, Eigen::VectorXd &mask,
                          Eigen::VectorXd &weighted, NormalEquations &equations) {
    Unwrap(system, v);
    const Eigen::Index n = system.size();
    residual.resize(n);
    mask.resize(n);
    weighted.resize(n);
    const PointColumns in{system.A.col(0).data(), system.A.col(1).data(), system.A.col(2).data(),
                          system.b.data(),        system.w.data(),        system.gate2.data()};
    return ClassifyAndAccumulateKernel(n, in, v.data(), residual.data(), mask.data(),
                                       weighted.data(), equations);
}

}  // namespace dorado::odometry::internal
