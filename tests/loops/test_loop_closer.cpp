// The loop closer on synthetic drives with a drifting odometry: two laps of a block close their
// loops and lose their drift; a drive without a revisit and a repeated street (two identical
// streets one after the other) accept no loop; injected false loops do not bend the map.
#include <gtest/gtest.h>

#include <cmath>

#include "dorado/loops/loop_closer.hpp"
#include "synthetic_drive.hpp"

namespace dorado::loops {
namespace {

struct LoopRun {
    LoopCloser closer;
    std::vector<mapping::WrittenPose> written;
    std::vector<Eigen::Isometry3d> truth;
};

void Drive(LoopRun &run) {
    for (const mapping::WrittenPose &pose : run.written) run.closer.Add(pose);
    run.closer.Finish();
}

// Largest position error of the corrected (or written) poses against the truth, after aligning
// the first pose (both start at the truth's first pose).
double MaxError(const std::vector<Eigen::Isometry3d> &truth, const Trajectory &estimate) {
    double worst = 0.0;
    for (std::size_t k = 0; k < truth.size(); ++k)
        worst = std::max(
            worst,
            (estimate.poses()[k].T_world_body.translation() - truth[k].translation()).norm());
    return worst;
}

double MaxWrittenError(const LoopRun &run) {
    double worst = 0.0;
    for (std::size_t k = 0; k < run.truth.size(); ++k)
        worst = std::max(
            worst, (run.written[k].T_world_base.translation() - run.truth[k].translation()).norm());
    return worst;
}

// Every accepted loop joins places within 5 m of each other in truth.
void ExpectAcceptedLoopsTrue(const LoopRun &run) {
    for (const LoopCandidate &c : run.closer.candidates()) {
        if (c.verdict != CandidateVerdict::kAccepted) continue;
        const std::size_t q = static_cast<std::size_t>(c.query_stamp_ns / 100'000'000);
        const std::size_t k = static_cast<std::size_t>(c.candidate_stamp_ns / 100'000'000);
        const Eigen::Isometry3d T_true = run.truth[k].inverse() * run.truth[q];
        const Vector6d error = LogSE3(T_true.inverse() * c.verification->T_candidate_query);
        EXPECT_LT(error.head<3>().norm(), 1.0) << c.query_submap << " -> " << c.candidate_submap;
    }
}

const std::vector<Eigen::Vector2d> kBlock{{0.0, 0.0}, {160.0, 0.0}, {160.0, 100.0}, {0.0, 100.0}};

LoopRun TwoLaps(double injected_false_fraction) {
    const test::StreetWorld world =
        test::StreetWorld::Make(5, -60.0, 220.0, -60.0, 160.0, {0.0, 160.0}, {0.0, 100.0});
    LoopClosureConfig config;
    config.injected_false_fraction = injected_false_fraction;
    LoopRun run{LoopCloser(config), {}, test::PathThrough(kBlock, 2, true)};
    run.written = test::DriftingDrive(world, run.truth, 3e-5, 21);
    Drive(run);
    return run;
}

// The clean two-lap run, shared by the tests that need it.
const LoopRun &CleanTwoLaps() {
    static const LoopRun run = TwoLaps(0.0);
    return run;
}

TEST(LoopCloser, TwoLapsOfABlockCloseTheirLoops) {
    const LoopRun &run = CleanTwoLaps();
    EXPECT_GE(run.closer.loops_accepted(), 3);
    ExpectAcceptedLoopsTrue(run);
    const double written = MaxWrittenError(run);
    const double corrected = MaxError(run.truth, run.closer.CorrectedTrajectory());
    EXPECT_GT(written, 2.0);              // the drive drifts ...
    EXPECT_LT(corrected, 0.3 * written);  // ... and its loops take most of it away
}

TEST(LoopCloser, InjectedFalseLoopsDoNotBendTheMap) {
    const LoopRun &clean = CleanTwoLaps();
    const LoopRun injected = TwoLaps(0.2);
    int injected_edges = 0;
    for (const LoopCandidate &c : injected.closer.candidates())
        if (c.verdict == CandidateVerdict::kInjected) {
            ++injected_edges;
            EXPECT_LT(c.switch_value, 0.5);
        }
    EXPECT_GE(injected_edges, 2);
    const double clean_error = MaxError(clean.truth, clean.closer.CorrectedTrajectory());
    const double injected_error = MaxError(injected.truth, injected.closer.CorrectedTrajectory());
    EXPECT_LT(injected_error, 1.1 * clean_error + 0.05);
}

TEST(LoopCloser, DriveWithoutRevisitAcceptsNoLoop) {
    const test::StreetWorld world =
        test::StreetWorld::Make(8, -60.0, 220.0, -60.0, 160.0, {0.0, 160.0}, {0.0, 100.0});
    LoopRun run{LoopCloser(LoopClosureConfig{}), {}, test::PathThrough(kBlock, 1, false)};
    run.written = test::DriftingDrive(world, run.truth, 1e-4, 22);
    Drive(run);
    EXPECT_EQ(run.closer.loops_accepted(), 0);
}

TEST(LoopCloser, RepeatedStreetAcceptsNoLoop) {
    // The same 200 m of street twice, one after the other: every place of the second looks like
    // one of the first, but lies 200 m away.
    const test::StreetWorld world =
        test::StreetWorld::Make(9, 0.0, 200.0, -60.0, 60.0, {}, {0.0}, 2, 200.0);
    LoopRun run{LoopCloser(LoopClosureConfig{}),
                {},
                test::PathThrough({{0.0, 0.0}, {400.0, 0.0}}, 1, false)};
    run.written = test::DriftingDrive(world, run.truth, 1e-4, 23);
    Drive(run);
    EXPECT_EQ(run.closer.loops_accepted(), 0);
    const double written = MaxWrittenError(run);
    EXPECT_LT(MaxError(run.truth, run.closer.CorrectedTrajectory()), written + 1e-6);
}

}  // namespace
}  // namespace dorado::loops
