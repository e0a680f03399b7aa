#include "dorado/sim/simulator.hpp"

#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>

#include "dorado/core/time.hpp"
#include "dorado/sim/bag_writer.hpp"
#include "dorado/sim/ground_truth.hpp"
#include "dorado/sim/imu_model.hpp"
#include "dorado/sim/moving_objects.hpp"
#include "dorado/sim/radar_model.hpp"
#include "dorado/sim/terrain.hpp"
#include "dorado/sim/vehicle.hpp"
#include "dorado/sim/world.hpp"

namespace dorado::sim {

namespace {

/// Evenly spaced sample times of one sensor [ns since start], within [0, duration].
struct Clock {
    int64_t period_ns;
    int64_t phase_ns;
    int64_t end_ns;
    int64_t index = 0;
    [[nodiscard]] int64_t Next() const { return phase_ns + index * period_ns; }
    [[nodiscard]] bool Done() const { return Next() > end_ns; }
    [[nodiscard]] std::size_t Count() const {
        return static_cast<std::size_t>((end_ns - phase_ns) / period_ns + 1);
    }
};

}  // namespace

SimulationResult Simulate(const SequenceConfig &config, const std::string &bag_path,
                          const BagTopics &topics, const ProgressCallback &progress) {
    config.Validate();
    const auto wall_start = std::chrono::steady_clock::now();
    const Terrain terrain(config.terrain, config.seed);
    const VehicleTrajectory vehicle(config, terrain);
    const StaticWorld world(config.world, terrain, vehicle.RouteSamples(), config.seed);
    const MovingObjects moving(config.dynamic, terrain, vehicle, config.seed);
    const RadarModel radar(config.radar, terrain, world, moving);
    ImuModel imu(config.imu, config.seed);
    MapperErrorModel mapper_error(config.ground_truth, config.seed);

    SimulationResult result;
    result.extrinsics.T_base_radar = config.radar.mount.Transform();
    result.extrinsics.T_base_imu = imu.T_base_imu();
    result.vehicle.half_wheelbase_m = config.vehicle.half_wheelbase_m;
    result.vehicle.base_height_m = config.vehicle.wheel_radius_m;  // the base origin's height
    const Eigen::Isometry3d &T_base_radar = result.extrinsics.T_base_radar;

    const int64_t start_ns = SecondsToNanos(config.start_time_s);
    const int64_t end_ns = SecondsToNanos(config.duration_s);
    auto period = [](double hz) { return static_cast<int64_t>(std::llround(1e9 / hz)); };
    // The sensors run on their own clocks; the radar's first scan comes a little after the start.
    Clock radar_clock{period(config.radar.rate_hz), period(config.radar.rate_hz) / 2, end_ns};
    Clock imu_clock{period(config.imu.rate_hz), 0, end_ns};
    Clock gt_clock{period(config.ground_truth.rate_hz), 0, end_ns};
    const std::size_t total_scans = radar_clock.Count();

    BagWriter bag(bag_path);
    SimulationStats &stats = result.stats;
    stats.duration_s = config.duration_s;
    stats.static_reflectors = world.reflectors().size();
    stats.moving_objects = moving.size();
    stats.points_per_scan_min = std::numeric_limits<std::size_t>::max();
    std::size_t n_points = 0, n_moving = 0, n_ground = 0, n_ghost = 0, n_clutter = 0;
    double sum_roll_rate2 = 0.0, sum_pitch_rate2 = 0.0;
    int64_t last_gt_ns = 0;

    while (!radar_clock.Done() || !imu_clock.Done() || !gt_clock.Done()) {
        // The next event in time order (ties: ground truth, IMU, radar).
        Clock *next = &gt_clock;
        for (Clock *c : {&imu_clock, &radar_clock}) {
            if (!c->Done() && (next->Done() || c->Next() < next->Next())) next = c;
        }
        const int64_t t_ns = next->Next();
        const double t = NanosToSeconds(t_ns);
        const int64_t stamp_ns = start_ns + t_ns;
        ++next->index;
        if (next == &gt_clock) {
            const Eigen::Isometry3d T_true = vehicle.Pose(t);
            const Eigen::Isometry3d T_reported =
                mapper_error.Perturb(T_true, NanosToSeconds(t_ns - last_gt_ns));
            last_gt_ns = t_ns;
            result.ground_truth.Append(stamp_ns, T_reported);
            result.true_trajectory.Append(stamp_ns, T_true);
            bag.WriteOdometry(topics.ground_truth, topics.world_frame, topics.base_frame, stamp_ns,
                              T_reported);
        } else if (next == &imu_clock) {
            bag.WriteImu(topics.imu, config.imu.frame_id, imu.Measure(t, stamp_ns, vehicle));
        } else {
            const Eigen::Isometry3d T_world_base = vehicle.Pose(t);
            const Twist twist = vehicle.Twist(t);
            // Rigid body (paper eq. 5): v_radar = R_base_radar^T (v_base + omega x t_base_radar).
            const Eigen::Vector3d v_radar_base =
                twist.v_base_mps + twist.omega_base_radps.cross(T_base_radar.translation());
            const Eigen::Vector3d v_radar = T_base_radar.linear().transpose() * v_radar_base;
            const Eigen::Isometry3d T_world_radar = T_world_base * T_base_radar;
            std::mt19937_64 rng(config.seed * 1000003ull +
                                static_cast<uint64_t>(radar_clock.index));
            SimulatedScan sim =
                radar.Measure(t, T_world_radar, T_world_base.linear() * v_radar_base, rng);
            sim.scan.stamp_ns = stamp_ns;
            bag.WriteRadar(topics.radar, sim.scan);
            result.twists.push_back({stamp_ns, twist, v_radar});

            const std::size_t n = sim.source.size();
            std::size_t moving_here = 0;
            for (const PointSource s : sim.source) {
                moving_here += s == PointSource::kMoving;
                n_ground += s == PointSource::kGround;
                n_ghost += s == PointSource::kGhost;
                n_clutter += s == PointSource::kClutter;
            }
            n_moving += moving_here;
            n_points += n;
            stats.points_per_scan_min = std::min(stats.points_per_scan_min, n);
            stats.points_per_scan_max = std::max(stats.points_per_scan_max, n);
            if (n > 0) {
                stats.max_dynamic_fraction =
                    std::max(stats.max_dynamic_fraction,
                             static_cast<double>(moving_here) / static_cast<double>(n));
            }
            const Eigen::Vector2d roll_pitch = RollPitchYaw(T_world_base.linear()).head<2>();
            stats.max_abs_roll_deg =
                std::max(stats.max_abs_roll_deg, RadToDeg(std::abs(roll_pitch.x())));
            stats.max_abs_pitch_deg =
                std::max(stats.max_abs_pitch_deg, RadToDeg(std::abs(roll_pitch.y())));
            sum_roll_rate2 += twist.omega_base_radps.x() * twist.omega_base_radps.x();
            sum_pitch_rate2 += twist.omega_base_radps.y() * twist.omega_base_radps.y();
            stats.max_speed_mps = std::max(stats.max_speed_mps, twist.v_base_mps.norm());
            ++stats.scans;
            if (progress) progress(stats.scans, total_scans);
        }
    }
    bag.Close();

    stats.imu_samples = static_cast<std::size_t>(imu_clock.index);
    stats.ground_truth_poses = result.ground_truth.size();
    const double points = std::max<double>(1.0, static_cast<double>(n_points));
    stats.points_per_scan_mean =
        static_cast<double>(n_points) / std::max<double>(1.0, static_cast<double>(stats.scans));
    if (stats.scans == 0) stats.points_per_scan_min = 0;
    stats.dynamic_fraction = static_cast<double>(n_moving) / points;
    stats.ground_fraction = static_cast<double>(n_ground) / points;
    stats.ghost_fraction = static_cast<double>(n_ghost) / points;
    stats.clutter_fraction = static_cast<double>(n_clutter) / points;
    const double scans = std::max<double>(1.0, static_cast<double>(stats.scans));
    stats.rms_roll_rate_radps = std::sqrt(sum_roll_rate2 / scans);
    stats.rms_pitch_rate_radps = std::sqrt(sum_pitch_rate2 / scans);
    stats.path_length_m = result.true_trajectory.PathLength();
    stats.seconds_taken =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    return result;
}

}  // namespace dorado::sim
