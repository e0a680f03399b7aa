// Time per 5 000-point radar scan of the whole mapper pipeline, per stage, on one core, for every
// registration method, with the smoother's default lag (1 s) and written at once (lag 0, a
// filter). Scans come from the tests' synthetic
// street (sparse, noisy, 3 % ghosts, an overtaking car) with a Doppler-like prior.
//
//   build/benchmarks/mapping/bench_mapper
//
// Counters: ms per scan of each stage (preprocess, registration, refinement, map_update, total),
// and the translation RPE per frame [mm] of the written poses (after Finish) against the simulated
// truth.
#include <benchmark/benchmark.h>

#include <random>

#include "dorado/mapping/radar_mapper.hpp"
#include "dorado/testing/street_scene.hpp"

namespace dorado::mapping {
namespace {

using namespace testing;

struct Sequence {
    std::vector<TruthSample> truth;
    std::vector<RadarScan> scans;
    std::vector<PointMask> masks;
    Extrinsics extrinsics;
};

const Sequence &GetSequence() {
    static const Sequence sequence = [] {
        Sequence s;
        s.extrinsics.T_base_radar.translation() = Eigen::Vector3d(1.8, 0.0, 1.2);
        const Eigen::Matrix3Xd world = MakeStreetWorld(5);
        s.truth = MakeDrive(60, 0.1);
        std::mt19937 rng(1);
        RadarSimOptions sim;  // 5 000 points per scan
        for (const auto &t : s.truth) {
            PointMask mask;
            s.scans.push_back(SimulateScan(world, t.T_world_base, s.extrinsics.T_base_radar,
                                           t.v_base, t.omega_base, Eigen::Matrix3Xd(3, 0),
                                           Eigen::Vector3d::Zero(), sim, rng, &mask));
            s.masks.push_back(mask);
        }
        return s;
    }();
    return sequence;
}

void BM_MapperPerScan(benchmark::State &state) {
    const Sequence &seq = GetSequence();
    MapperConfig config;
    config.method = static_cast<RegistrationMethod>(state.range(0));
    if (state.range(1) == 0) config.smoother.lag_s = 0.0;
    PriorNoiseConfig noise;
    StageTimes sum;
    double rpe_sum = 0.0;
    int scans = 0, fallbacks = 0;
    std::size_t last_map_size = 0;
    double source_sum = 0.0;
    for (auto _ : state) {
        state.PauseTiming();
        RadarMapper mapper(config, seq.extrinsics);
        std::mt19937 rng(2);
        std::normal_distribution<double> n(0.0, 1.0);
        std::vector<Eigen::Isometry3d> poses;  // the newest: where the next prior starts
        std::vector<WrittenPose> written;
        state.ResumeTiming();
        for (std::size_t k = 0; k < seq.scans.size(); ++k) {
            MotionPrior prior;
            if (k > 0) {
                Twist twist;  // Doppler-odometry-like: v noisy, roll rate unobserved
                twist.v_base_mps =
                    seq.truth[k - 1].v_base + 0.03 * Eigen::Vector3d(n(rng), n(rng), n(rng));
                twist.omega_base_radps =
                    seq.truth[k - 1].omega_base + Eigen::Vector3d(0, 0.02 * n(rng), 0.005 * n(rng));
                twist.omega_base_radps.x() = 0.0;
                twist.covariance.topLeftCorner<3, 3>() = Eigen::Matrix3d::Identity() * 9e-4;
                twist.covariance.bottomRightCorner<3, 3>() =
                    Eigen::Vector3d(0.0, 4e-4, 2.5e-5).asDiagonal();
                prior = PriorFromDoppler(poses.back(), twist, 0.1, noise);
            }
            MapperInput input;
            input.prior = prior;
            input.dt_s = 0.1;
            input.static_mask = seq.masks[k];
            RegistrationResult r = mapper.Register(seq.scans[k], input);
            poses.push_back(r.T_world_base);
            for (WrittenPose &w : r.written) written.push_back(std::move(w));
            last_map_size = mapper.local_map().size();
            source_sum += r.source_points;
            if (k == 0) continue;  // the first scan only starts the map
            sum.preprocess_ms += r.times.preprocess_ms;
            sum.registration_ms += r.times.registration_ms;
            sum.alignment_ms += r.times.alignment_ms;
            sum.refinement_ms += r.times.refinement_ms;
            sum.map_update_ms += r.times.map_update_ms;
            sum.total_ms += r.times.total_ms;
            fallbacks += r.fallback();
            ++scans;
        }
        for (WrittenPose &w : mapper.Finish()) written.push_back(std::move(w));
        state.PauseTiming();
        for (std::size_t k = 1; k < written.size() && k < seq.truth.size(); ++k) {
            const Eigen::Isometry3d true_step =
                seq.truth[k - 1].T_world_base.inverse() * seq.truth[k].T_world_base;
            const Eigen::Isometry3d step =
                written[k - 1].T_world_base.inverse() * written[k].T_world_base;
            rpe_sum += (true_step.inverse() * step).translation().norm();
        }
        state.ResumeTiming();
    }
    state.counters["preprocess_ms"] = sum.preprocess_ms / scans;
    state.counters["registration_ms"] = sum.registration_ms / scans;
    state.counters["pcl_align_ms"] = sum.alignment_ms / scans;
    state.counters["refinement_ms"] = sum.refinement_ms / scans;
    state.counters["map_update_ms"] = sum.map_update_ms / scans;
    state.counters["total_ms"] = sum.total_ms / scans;
    state.counters["rpe_mm"] = 1000.0 * rpe_sum / scans;
    state.counters["map_points"] = static_cast<double>(last_map_size);
    state.counters["source_points"] = source_sum / scans;
    state.counters["fallbacks"] = static_cast<double>(fallbacks) / state.iterations();
    state.SetLabel(std::string(ToString(config.method)) + (state.range(1) ? "" : "+lag0"));
}

BENCHMARK(BM_MapperPerScan)
    ->ArgsProduct({{0, 1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2);

}  // namespace
}  // namespace dorado::mapping

BENCHMARK_MAIN();
