#include "preflight.hpp"

#include <Eigen/Geometry>
#include <cstdio>

#include "dorado/core/angles.hpp"
#include "dorado/core/lie.hpp"
#include "dorado/io/dataset.hpp"

namespace dorado::apps {

namespace {

/// Radar messages read before a recording whose scans are all unreadable is refused.
constexpr std::size_t kFirstScans = 10;

void CheckFirstScans(const io::DatasetConfig &one, const std::string &radar,
                     const std::string &out_dir) {
    const std::string kept = out_dir.empty() ? "" : "; " + out_dir + " was left as it was";
    const std::string who = radar.empty() ? "" : "radar " + radar + ": ";
    std::unique_ptr<io::DatasetReader> reader;
    try {
        reader = io::OpenDataset(one);
    } catch (const io::DatasetError &e) {
        throw io::DatasetError(who + e.what() + kept);
    }
    io::DatasetEvent event;
    std::size_t bad = 0;
    std::string first_problem;
    try {
        while (reader->Next(event)) {
            if (event.kind == io::DatasetEvent::Kind::kRadarScan) return;
            if (event.kind != io::DatasetEvent::Kind::kBadScan) continue;
            if (bad++ == 0) first_problem = event.problem;
            if (bad == kFirstScans) break;
        }
    } catch (const io::DatasetError &e) {
        throw io::DatasetError(who + e.what() + kept);
    }
    if (bad == 0) return;  // no scan at all: the command says so
    throw io::DatasetError(
        who + reader->source() + ": " +
        (bad == kFirstScans ? "the first " + std::to_string(bad) : "all " + std::to_string(bad)) +
        " radar scans cannot be read; the first: " + first_problem + kept);
}

std::string MountText(const Eigen::Isometry3d &T) {
    const Eigen::Vector3d t = T.translation();
    const Eigen::Vector3d rpy = RadToDeg(RollPitchYaw(T.linear()));
    char text[160];
    std::snprintf(text, sizeof(text),
                  "translation_m [%.3f, %.3f, %.3f], rotation_rpy_deg [%.2f, %.2f, %.2f]", t.x(),
                  t.y(), t.z(), rpy.x(), rpy.y(), rpy.z());
    return text;
}

}  // namespace

void CheckBeforeWork(const io::DatasetConfig &dataset, const std::string &out_dir) {
    if (dataset.radars.size() < 2) return CheckFirstScans(dataset, "", out_dir);
    for (std::size_t k = 0; k < dataset.radars.size(); ++k)
        CheckFirstScans(io::ForRadar(dataset, k), dataset.radars[k].name, out_dir);
}

void StateAssumptions(const io::DatasetConfig &dataset, const std::string &arg,
                      const std::string &command) {
    const std::string mount = MountText(dataset.extrinsics.T_base_radar);
    if (dataset.mount_source == io::MountSource::kHuginDefault) {
        const io::FieldMap &f = dataset.fields;
        std::fprintf(stderr,
                     "%s: %s has no dataset description: read as the paper's Hugin recording: "
                     "radar topic %s, fields x=%s y=%s z=%s doppler=%s power=%s (sign %+g), no "
                     "IMU, the radar mounted at %s (the paper's launch file). Another radar "
                     "needs a description saying its own (docs/datasets.md)\n",
                     command.c_str(), arg.c_str(), dataset.rosbag.radar_topic.c_str(), f.x.c_str(),
                     f.y.c_str(), f.z.c_str(), f.doppler.c_str(), f.power.c_str(), f.doppler_sign,
                     mount.c_str());
    } else if (dataset.mount_source == io::MountSource::kIdentityAssumed) {
        std::fprintf(stderr,
                     "%s: %s: no extrinsics.T_base_radar: the radar is assumed at the base origin, "
                     "unrotated (%s); write the mount to state it\n",
                     command.c_str(), arg.c_str(), mount.c_str());
    }
}

}  // namespace dorado::apps
