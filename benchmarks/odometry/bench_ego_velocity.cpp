// Time per scan of the ego-velocity estimator (pre-filter, weights, RANSAC, refit, covariance) on
// Hugin-like synthetic scans. Run: build/benchmarks/odometry/bench_ego_velocity
#include <benchmark/benchmark.h>

#include <vector>

#include "dorado/odometry/ego_velocity.hpp"
#include "dorado/testing/doppler_scan.hpp"

namespace {

using dorado::odometry::EgoVelocityConfig;
using dorado::odometry::EgoVelocityEstimator;
using dorado::odometry::RobustMethod;

// A few different scans per size so that the branch predictor does not learn one.
std::vector<dorado::RadarScan> Scans(int points, double dynamic_fraction, bool coherent) {
    std::vector<dorado::RadarScan> scans;
    for (int k = 0; k < 8; ++k) {
        dorado::testing::SceneOptions o;
        o.points = points;
        o.dynamic_fraction = dynamic_fraction;
        o.coherent_crowd = coherent;
        o.seed = 100 + k;
        scans.push_back(dorado::testing::MakeScan(o).scan);
    }
    return scans;
}

void Run(benchmark::State &state, EgoVelocityConfig config, double dynamic_fraction,
         bool coherent) {
    const auto scans = Scans(static_cast<int>(state.range(0)), dynamic_fraction, coherent);
    EgoVelocityEstimator estimator(config);
    std::size_t k = 0;
    double iterations = 0;
    for (auto _ : state) {
        const auto result = estimator.Estimate(scans[k++ % scans.size()]);
        iterations += result.iterations;
        benchmark::DoNotOptimize(result.v_radar_mps.data());
    }
    state.SetItemsProcessed(state.iterations() * state.range(0));
    state.counters["ransac_iters"] = iterations / static_cast<double>(state.iterations());
}

void BM_Ransac_10pctDynamic(benchmark::State &s) {
    Run(s, {}, 0.1, false);
}
void BM_Ransac_30pctObjects(benchmark::State &s) {
    Run(s, {}, 0.3, false);
}
void BM_Ransac_50pctBus(benchmark::State &s) {
    Run(s, {}, 0.5, true);
}
void BM_TrimmedIrls_10pctDynamic(benchmark::State &s) {
    EgoVelocityConfig c;
    c.method = RobustMethod::kTrimmedIrls;
    Run(s, c, 0.1, false);
}

#define SIZES ->Arg(500)->Arg(2000)->Arg(5000)->Arg(20000)->Unit(benchmark::kMicrosecond)
BENCHMARK(BM_Ransac_10pctDynamic) SIZES;
BENCHMARK(BM_Ransac_30pctObjects) SIZES;
BENCHMARK(BM_Ransac_50pctBus) SIZES;
BENCHMARK(BM_TrimmedIrls_10pctDynamic) SIZES;

}  // namespace

BENCHMARK_MAIN();
