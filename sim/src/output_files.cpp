// The files `dorado simulate` writes next to the bag: ground truth, true twists, the dataset
// description every other command reads, and a summary.
#include <nlohmann/json.hpp>

#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <iomanip>

#include "dorado/io/atomic_file.hpp"
#include "dorado/io/dataset_config.hpp"
#include "dorado/io/trajectory_io.hpp"
#include "dorado/sim/simulator.hpp"

namespace dorado::sim {

namespace {

/// A stamp as seconds with all nine decimals (doubles would round at 1e9 s).
std::string StampSeconds(int64_t stamp_ns) {
    char text[32];
    std::snprintf(text, sizeof(text), "%" PRId64 ".%09" PRId64, stamp_ns / 1'000'000'000,
                  stamp_ns % 1'000'000'000);
    return text;
}

void WriteTrueTwists(const std::string &path, const std::vector<TrueTwist> &twists) {
    io::WriteFileAtomically(path, [&](std::ostream &out) {
        out << "t,v_base_x,v_base_y,v_base_z,omega_x,omega_y,omega_z,v_radar_x,v_radar_y,v_radar_"
               "z\n";
        out << std::setprecision(12);
        for (const auto &tw : twists) {
            out << StampSeconds(tw.stamp_ns);
            for (const auto *v :
                 {&tw.twist_base.v_base_mps, &tw.twist_base.omega_base_radps, &tw.v_radar}) {
                out << ',' << v->x() << ',' << v->y() << ',' << v->z();
            }
            out << '\n';
        }
    });
}

io::DatasetConfig DescribeDataset(const SequenceConfig &config, const SimulationResult &result,
                                  const BagTopics &topics) {
    io::DatasetConfig d;
    d.name = config.name;
    d.reader = io::ReaderKind::kRosbag;
    d.rosbag.path = "data.bag";  // relative paths are taken relative to dataset.yaml
    d.rosbag.radar_topic = topics.radar;
    d.rosbag.imu_topic = topics.imu;
    d.rosbag.ground_truth_topic = topics.ground_truth;
    d.ground_truth.path = "ground_truth.tum";
    d.ground_truth.format = io::TrajectoryFormat::kTum;
    d.fields = io::FieldMap{};  // the Hugin layout
    d.extrinsics = result.extrinsics;
    d.vehicle = result.vehicle;
    // The radar's datasheet: what a user of a real sensor would write.
    d.radar.range_sigma_m = config.radar.range_sigma_m;
    d.radar.azimuth_sigma_deg = config.radar.azimuth_sigma_deg;
    d.radar.elevation_sigma_deg = config.radar.elevation_sigma_deg;
    d.radar.doppler_unambiguous_mps = config.radar.doppler_unambiguous_mps;
    return d;
}

nlohmann::json StatsJson(const SequenceConfig &config, const SimulationStats &s) {
    return {{"sequence", config.name},
            {"seed", config.seed},
            {"duration_s", s.duration_s},
            {"scans", s.scans},
            {"points_per_scan",
             {{"mean", s.points_per_scan_mean},
              {"min", s.points_per_scan_min},
              {"max", s.points_per_scan_max}}},
            {"dynamic_fraction", s.dynamic_fraction},
            {"max_dynamic_fraction", s.max_dynamic_fraction},
            {"ground_fraction", s.ground_fraction},
            {"ghost_fraction", s.ghost_fraction},
            {"clutter_fraction", s.clutter_fraction},
            {"imu_samples", s.imu_samples},
            {"ground_truth_poses", s.ground_truth_poses},
            {"static_reflectors", s.static_reflectors},
            {"moving_objects", s.moving_objects},
            {"path_length_m", s.path_length_m},
            {"max_speed_mps", s.max_speed_mps},
            {"rms_roll_rate_radps", s.rms_roll_rate_radps},
            {"rms_pitch_rate_radps", s.rms_pitch_rate_radps},
            {"max_abs_roll_deg", s.max_abs_roll_deg},
            {"max_abs_pitch_deg", s.max_abs_pitch_deg},
            {"seconds_taken", s.seconds_taken}};
}

}  // namespace

SimulationResult SimulateToDirectory(const SequenceConfig &config, const std::string &out_dir,
                                     const ProgressCallback &progress) {
    namespace fs = std::filesystem;
    io::MakeDirectories(out_dir);
    const fs::path dir(out_dir);
    const BagTopics topics;
    // The bag is written under a temporary name and renamed at the end, like the other files.
    const std::string bag_tmp = (dir / "data.bag.tmp").string();
    SimulationResult result = Simulate(config, bag_tmp, topics, progress);
    std::error_code ec;
    fs::rename(bag_tmp, dir / "data.bag", ec);
    if (ec)
        throw std::runtime_error((dir / "data.bag").string() + ": cannot rename: " + ec.message());
    io::WriteTum((dir / "ground_truth.tum").string(), result.ground_truth);
    // The exact poses at the same stamps: scoring against them separates an estimator's error
    // from the reference's own (lidar-mapper-like) error.
    io::WriteTum((dir / "true_trajectory.tum").string(), result.true_trajectory);
    WriteTrueTwists((dir / "true_twist.csv").string(), result.twists);
    const std::string yaml = io::DatasetConfigToYaml(DescribeDataset(config, result, topics));
    io::WriteFileAtomically((dir / "dataset.yaml").string(), [&](std::ostream &out) {
        out << "# Written by `dorado simulate` (sequence " << config.name << ", seed "
            << config.seed << "). Every dorado command reads this description.\n"
            << yaml;
    });
    io::WriteFileAtomically((dir / "simulation.json").string(), [&](std::ostream &out) {
        out << StatsJson(config, result.stats).dump(2) << "\n";
    });
    return result;
}

}  // namespace dorado::sim
