// Every installed library end to end: scans of a static street from a radar driving straight along
// +x at 5 m/s are written as a scan folder (dorado::io's folder layout: one float32 .bin per scan
// with columns x y z power doppler, a timestamps file, a dataset description), read back through
// dorado::io, the mapper's settings read through dorado::config, and every scan run through
// dorado::frontend (Doppler odometry, dorado::odometry; scan-to-map registration, dorado::mapping).
// Truth: the base is at x = 5 m/s * t, y = z = 0, heading 0. Usage: mapper_consumer WORK_DIR
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <vector>

#include "dorado/config/map_config.hpp"
#include "dorado/core/angles.hpp"
#include "dorado/frontend/radar_front_end.hpp"
#include "dorado/io/dataset.hpp"
#include "dorado/io/dataset_config.hpp"

namespace fs = std::filesystem;

namespace {

constexpr double kSpeedMps = 5.0, kDtS = 0.1;
constexpr int kScans = 30;
const Eigen::Vector3d kRadarInBase(1.5, 0.0, 1.0);  // the mount: forward, no rotation

// The street: facades at |y| = 8 m that step back to 11 m every other 10 m (with the faces of the
// steps, which face along the street), and poles at |y| = 5 m every 10 m.
std::vector<Eigen::Vector3d> Street() {
    std::vector<Eigen::Vector3d> points;
    for (double x = -20.0; x < 120.0; x += 0.4) {
        const double y = std::fmod(x + 100.0, 20.0) < 10.0 ? 8.0 : 11.0;
        for (double z = 0.0; z < 6.0; z += 0.5) {
            points.emplace_back(x, y, z);
            points.emplace_back(x, -y, z);
        }
    }
    for (double x = -20.0; x < 120.0; x += 10.0) {
        for (double z = 0.0; z < 6.0; z += 0.5) {
            for (double y = 8.0; y <= 11.0; y += 0.4) {
                points.emplace_back(x, y, z);
                points.emplace_back(x, -y, z);
            }
        }
        for (double z = 0.0; z < 4.0; z += 0.25) {
            points.emplace_back(x + 5.0, 5.0, z);
            points.emplace_back(x + 5.0, -5.0, z);
        }
    }
    return points;
}

// Scan k: about 600 of the points the radar sees (range 1-60 m, azimuth +-70 deg, elevation +-20
// deg), each with its radial Doppler (positive = receding: a static point seen from a radar moving
// at v reads -d . v), written as rows of float32 x y z power doppler.
void WriteScan(const std::vector<Eigen::Vector3d> &street, int k, const fs::path &file,
               std::mt19937 &rng) {
    const Eigen::Vector3d radar = Eigen::Vector3d(kSpeedMps * kDtS * k, 0.0, 0.0) + kRadarInBase;
    const Eigen::Vector3d v_radar(kSpeedMps, 0.0, 0.0);
    std::vector<float> rows;
    for (const Eigen::Vector3d &point : street) {
        const Eigen::Vector3d p = point - radar;
        const double r = p.norm();
        if (r < 1.0 || r > 60.0 || std::abs(std::atan2(p.y(), p.x())) > 1.22 ||
            std::abs(std::asin(p.z() / r)) > 0.35)
            continue;
        const Eigen::Vector3d d = p / r;
        rows.insert(rows.end(),
                    {float(p.x()), float(p.y()), float(p.z()), 20.0F, float(-d.dot(v_radar))});
    }
    // A radar sees some of the surfaces each time: a random subset, different in every scan.
    std::vector<float> kept;
    std::bernoulli_distribution keep(std::min(1.0, 600.0 / double(rows.size() / 5)));
    for (std::size_t i = 0; i < rows.size(); i += 5)
        if (keep(rng)) kept.insert(kept.end(), rows.begin() + long(i), rows.begin() + long(i) + 5);
    std::ofstream(file, std::ios::binary)
        .write(reinterpret_cast<const char *>(kept.data()), long(kept.size() * sizeof(float)));
}

// The scan folder and its description in `dir`; the description's path.
std::string WriteDataset(const fs::path &dir) {
    fs::create_directories(dir / "scans");
    const std::vector<Eigen::Vector3d> street = Street();
    std::mt19937 rng(42);
    std::ofstream times(dir / "times.txt");
    for (int k = 0; k < kScans; ++k) {
        char name[16];
        std::snprintf(name, sizeof(name), "%05d.bin", k);
        WriteScan(street, k, dir / "scans" / name, rng);
        times << 100.0 + kDtS * k << '\n';
    }
    std::ofstream(dir / "dataset.yaml") << R"(name: consumer_street
reader: folder
folder: {scans_dir: scans, extension: .bin, timestamps_file: times.txt,
         columns: [x, y, z, power, doppler]}
fields: {range: "", azimuth: "", elevation: "", power: power, doppler: doppler}
extrinsics:
  T_base_radar: {translation_m: [1.5, 0.0, 1.0], rotation_rpy_deg: [0.0, 0.0, 0.0]}
vehicle: {half_wheelbase_m: 1.4}
)";
    std::ofstream(dir / "mapper.yaml") << "mapper: {max_range_m: 60.0}\n";
    return (dir / "dataset.yaml").string();
}

}  // namespace

int main(int argc, char **argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: mapper_consumer WORK_DIR\n");
        return 2;
    }
    const fs::path dir = fs::path(argv[1]) / "street";
    fs::remove_all(dir);
    try {
        const dorado::io::DatasetConfig dataset = dorado::io::LoadDatasetConfig(WriteDataset(dir));
        const auto map_config = dorado::config::LoadMapConfig((dir / "mapper.yaml").string());
        dorado::frontend::FrontEndConfig config;
        config.mapper = map_config.mapper;
        config.prior_noise = map_config.prior;
        dorado::frontend::RadarFrontEnd front_end(config, dataset.extrinsics, dataset.vehicle);
        auto reader = dorado::io::OpenDataset(dataset);
        dorado::io::DatasetEvent event;
        int scans = 0, registered = 0, backwards = 0;
        double previous_x = 0.0;
        Eigen::Isometry3d last = Eigen::Isometry3d::Identity();
        while (reader->Next(event)) {
            if (event.kind != dorado::io::DatasetEvent::Kind::kRadarScan) continue;
            const dorado::frontend::FrontEndResult result = front_end.Process(event.scan);
            if (!result.accepted) continue;
            ++scans;
            registered += result.registration.fallback() ? 0 : 1;
            backwards += result.T_world_base.translation().x() < previous_x ? 1 : 0;
            previous_x = result.T_world_base.translation().x();
            last = result.T_world_base;
        }
        // The base starts at the origin (the first scan's pose) and drives (kScans - 1) steps.
        const double expected_x = kSpeedMps * kDtS * (kScans - 1);
        const Eigen::Vector3d t = last.translation();
        const double heading_deg =
            dorado::RadToDeg(std::atan2(last.linear()(1, 0), last.linear()(0, 0)));
        std::printf(
            "scans %d (registered %d, steps backwards %d): last pose x %.3f m (expected "
            "%.3f), y %.3f, z %.3f, heading %.2f deg\n",
            scans, registered, backwards, t.x(), expected_x, t.y(), t.z(), heading_deg);
        const bool ok = scans == kScans && registered >= kScans - 2 && backwards == 0 &&
                        std::abs(t.x() - expected_x) < 0.15 && std::abs(t.y()) < 0.15 &&
                        std::abs(t.z()) < 0.15 && std::abs(heading_deg) < 1.0;
        std::printf("%s\n", ok ? "OK" : "FAILED: the mapped trajectory is not the driven one");
        fs::remove_all(dir);
        return ok ? 0 : 1;
    } catch (const std::exception &e) {
        std::fprintf(stderr, "mapper_consumer: %s\n", e.what());
        return 1;
    }
}
