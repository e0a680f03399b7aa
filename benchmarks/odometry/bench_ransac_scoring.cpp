// RANSAC hypothesis scoring, next to the paper's reference RANSAC (reference_ransac.hpp), on
// crowded scans (dorado/testing/crowd_scan.hpp) of 500, 900, 2 200 and 5 000 points with 10, 25,
// 40 and 50 % of the points on coherent movers. Prints, per size and mover share:
//  - the whole estimator (dorado's EgoVelocityEstimator::Estimate; the reference's Estimate):
//    median and p95 thread CPU time per scan (fastest of `reps` runs per scan) and the speed-up;
//  - the scoring alone: ns per point per hypothesis of dorado's vectorised scoring
//    (internal::ScoreCells over the structure-of-arrays ScoringSet) and of the reference's scalar
//    loop (count |d . v - b| > gate over every point), and the fraction of the arithmetic limit
//    the vectorised one reaches. The limit: 4 multiply-adds per point (d . v - b, r^2), at 2 vector
//    multiply-adds per cycle of 4 doubles (AVX2), i.e. 0.5 cycle per point at the clock given
//    (default: /proc/cpuinfo's "cpu MHz").
// Run: build/benchmarks/odometry/bench_ransac_scoring [scans=50] [reps=3] [MHz]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "dorado/odometry/ego_velocity.hpp"
#include "dorado/testing/crowd_scan.hpp"
#include "reference_ransac.hpp"
#include "robust_fit.hpp"  // odometry/src: the scoring kernel itself

namespace {

namespace internal = dorado::odometry::internal;

double ThreadNs() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return 1e9 * static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec);
}

double Quantile(std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5)];
}

double CpuMhz() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("cpu MHz", 0) == 0)
            return std::atof(line.substr(line.find(':') + 1).c_str());
    return 0.0;
}

// The scan as the scoring sees it: unit directions, b = -doppler, a 3-sigma gate, 12 x 3 cells
// by azimuth and elevation (the estimator's defaults).
internal::DopplerSystem System(const dorado::RadarScan &scan) {
    internal::DopplerSystem s;
    const Eigen::Index n = scan.size();
    s.Resize(n);
    s.num_cells = 36;
    for (Eigen::Index i = 0; i < n; ++i) {
        const Eigen::Vector3d d = scan.xyz_radar.col(i).normalized();
        s.A.row(i) = d.transpose();
        s.b[i] = -scan.doppler_mps[i];
        s.w[i] = 1.0;
        s.gate2[i] = 0.15 * 0.15;
        const double az = std::atan2(d.y(), d.x()), el = std::asin(d.z());
        const int ca = std::clamp(static_cast<int>((az + M_PI / 3) / (2 * M_PI / 3) * 12), 0, 11);
        const int ce = std::clamp(static_cast<int>((el + 0.35) / 0.7 * 3), 0, 2);
        s.cell[i] = ce * 12 + ca;
    }
    return s;
}

struct Scoring {
    double dorado_ns = 0, reference_ns = 0;  // per point per hypothesis
};

// Scores `hypotheses` velocities near the truth on one scan, both ways; fastest of `reps`.
Scoring TimeScoring(const dorado::RadarScan &scan, const Eigen::Vector3d &v_true, int reps,
                    std::mt19937_64 &rng) {
    constexpr int kHypotheses = 100;
    const internal::DopplerSystem s = System(scan);
    internal::ScoringSet set;
    set.Build(s, 0);
    std::normal_distribution<double> noise(0.0, 0.3);
    std::vector<Eigen::Vector3d> hypotheses(kHypotheses);
    for (auto &h : hypotheses) h = v_true + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    std::vector<double> quality(static_cast<std::size_t>(s.num_cells));
    std::vector<int> count(static_cast<std::size_t>(s.num_cells));
    const double *ax = s.A.col(0).data(), *ay = s.A.col(1).data(), *az = s.A.col(2).data(),
                 *b = s.b.data();
    const Eigen::Index n = s.size();
    double best_d = 1e30, best_r = 1e30;
    long sink = 0;
    for (int r = 0; r < reps; ++r) {
        double t0 = ThreadNs();
        for (const auto &h : hypotheses)
            sink += internal::ScoreCells(set, h.data(), quality.data(), count.data());
        best_d = std::min(best_d, ThreadNs() - t0);
        t0 = ThreadNs();
        for (const auto &h : hypotheses) {
            Eigen::Index outliers = 0;  // reference_ransac.hpp's loop, on the same columns
            for (Eigen::Index i = 0; i < n; ++i)
                outliers += std::abs(ax[i] * h.x() + ay[i] * h.y() + az[i] * h.z() - b[i]) > 0.15;
            sink += outliers;
        }
        best_r = std::min(best_r, ThreadNs() - t0);
    }
    if (sink == 42) std::puts("");  // keeps the loops
    const double work = static_cast<double>(n) * kHypotheses;
    return {best_d / work, best_r / work};
}

}  // namespace

int main(int argc, char **argv) {
    const int scans = argc > 1 ? std::atoi(argv[1]) : 50;
    const int reps = argc > 2 ? std::atoi(argv[2]) : 3;
    const double mhz = argc > 3 ? std::atof(argv[3]) : CpuMhz();
    const double limit_ns = mhz > 0 ? 0.5 / (mhz * 1e-3) : 0.0;  // 0.5 cycle per point
    std::printf(
        "%d crowded scans per row, fastest of %d runs, thread CPU time; clock %.0f MHz: "
        "arithmetic limit %.3f ns per point per hypothesis\n",
        scans, reps, mhz, limit_ns);
    std::printf("%6s %6s | %-27s | %-15s | %7s | %-27s\n", "points", "movers",
                "dorado: median p95 [ms] p95/med", "reference [ms]", "speedup",
                "scoring ns/pt/hyp dorado ref, limit");
    std::mt19937_64 rng(7);
    for (const int points : {500, 900, 2200, 5000}) {
        for (const double movers : {0.10, 0.25, 0.40, 0.50}) {
            std::vector<dorado::testing::CrowdScene> scenes;
            for (int k = 0; k < scans; ++k) {
                dorado::testing::CrowdOptions o;
                o.points = points;
                o.mover_fraction = movers;
                o.seed = 9000 + static_cast<uint64_t>(k);
                scenes.push_back(dorado::testing::MakeCrowdScan(o));
            }
            dorado::odometry::EgoVelocityEstimator estimator{dorado::odometry::EgoVelocityConfig{}};
            dorado::benchmarks::ReferenceRansac reference;
            std::vector<double> t_dorado, t_reference, ns_dorado, ns_reference;
            int failed = 0;
            volatile double sink = 0.0;
            for (const auto &scene : scenes) {
                const auto &scan = scene.scan.scan;
                double best_d = 1e30, best_r = 1e30;
                for (int r = 0; r < reps; ++r) {
                    double t0 = ThreadNs();
                    const auto result = estimator.Estimate(scan);
                    best_d = std::min(best_d, ThreadNs() - t0);
                    failed += r == 0 && !result.valid();
                    Eigen::Vector3d v = Eigen::Vector3d::Zero();
                    t0 = ThreadNs();
                    reference.Estimate(scan, v);
                    best_r = std::min(best_r, ThreadNs() - t0);
                    sink = sink + v.sum();  // the reference's result is used
                }
                t_dorado.push_back(best_d * 1e-6);
                t_reference.push_back(best_r * 1e-6);
                const Scoring sc = TimeScoring(scan, scene.v_radar, reps, rng);
                ns_dorado.push_back(sc.dorado_ns);
                ns_reference.push_back(sc.reference_ns);
            }
            const double med = Quantile(t_dorado, 0.5), p95 = Quantile(t_dorado, 0.95);
            const double ref = Quantile(t_reference, 0.5), nsd = Quantile(ns_dorado, 0.5);
            std::printf(
                "%6d %5.0f%% | %7.3f %7.3f %5.2fx      | %7.3f         | %6.1fx | %5.3f "
                "%5.3f  %3.0f %% of limit   failed %d\n",
                points, 100 * movers, med, p95, p95 / med, ref, ref / med, nsd,
                Quantile(ns_reference, 0.5), limit_ns > 0 ? 100 * limit_ns / nsd : 0.0, failed);
        }
    }
    return 0;
}
