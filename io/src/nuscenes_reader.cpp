// nuScenes (H. Caesar et al., CVPR 2020) radar sweeps in their own files, as
// nutonomy/nuscenes-devkit reads them: the JSON tables index the scene's sweeps
// (nuscenes_tables.hpp), each sweep a binary PCD v0.7 of the Continental ARS408's clusters: FIELDS
// x y z dyn_prop id rcs vx vy vx_comp vy_comp is_quality_valid ambig_state x_rms y_rms
// invalid_state pdh0 vx_rms vy_rms, SIZE 4 4 4 1 2 4 4 4 4 4 1 1 1 1 1 1 1 1, TYPE F F F I I F F F
// F F I I I I I I I I. A scan is one sweep of one of the channels read, in time order, with every
// cluster (the devkit's optional state filters are not applied).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "nuscenes_tables.hpp"
#include "readers.hpp"

namespace dorado::io {

namespace {

constexpr int64_t kNanosPerMicro = 1000;

// One PCD field as the header describes it.
struct PcdField {
    std::string name;
    char type = 'F';
    std::size_t size = 4, count = 1, offset = 0;
};

// Decodes a binary PCD v0.7 radar sweep into a scan; throws DecodeError naming the field.
RadarScan DecodeSweep(const std::string &file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw DecodeError("cannot open");
    std::vector<PcdField> fields;
    std::size_t points = 0;
    std::string line, data;
    std::map<std::string, std::vector<std::string>> header;
    while (data.empty() && std::getline(in, line)) {
        std::istringstream tokens(line);
        std::string key;
        tokens >> key;
        if (key.empty() || key[0] == '#') continue;
        for (std::string v; tokens >> v;) header[key].push_back(v);
        if (key == "DATA") data = header[key].empty() ? "?" : header[key][0];
    }
    if (data != "binary")
        throw DecodeError("not a binary PCD (DATA " + (data.empty() ? "missing" : data) + ")");
    const auto &names = header["FIELDS"], &sizes = header["SIZE"], &types = header["TYPE"];
    auto counts = header["COUNT"];
    if (counts.empty()) counts.assign(names.size(), "1");
    if (names.empty() || sizes.size() != names.size() || types.size() != names.size() ||
        counts.size() != names.size())
        throw DecodeError("the header's FIELDS, SIZE, TYPE and COUNT differ in length");
    std::size_t step = 0;
    for (std::size_t i = 0; i < names.size(); ++i) {
        PcdField f{names[i], types[i].empty() ? '?' : types[i][0], 0, 0, step};
        try {
            f.size = std::stoul(sizes[i]);
            f.count = std::stoul(counts[i]);
            points = header["POINTS"].empty() ? 0 : std::stoul(header["POINTS"][0]);
        } catch (const std::logic_error &) {
            throw DecodeError("field '" + f.name + "': SIZE, COUNT or POINTS is not a number");
        }
        if (f.size == 0 || f.size > 8 || f.count == 0 || f.count > 65536)
            throw DecodeError("field '" + f.name + "': SIZE " + std::to_string(f.size) +
                              " or COUNT " + std::to_string(f.count) + " out of range");
        step += f.size * f.count;
        fields.push_back(f);
    }
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)),
                                  std::istreambuf_iterator<char>());
    if (points > bytes.size() / step)  // step > 0: every field has SIZE and COUNT >= 1
        throw DecodeError("truncated: " + std::to_string(points) + " points of " +
                          std::to_string(step) + " bytes need " + std::to_string(points * step) +
                          " bytes after the header, the file has " + std::to_string(bytes.size()));
    // The fields dorado uses, each a float32 in nuScenes' schema.
    const auto offset = [&](const char *name) {
        const auto it = std::find_if(fields.begin(), fields.end(),
                                     [&](const PcdField &f) { return f.name == name; });
        if (it == fields.end()) throw DecodeError(std::string("missing field '") + name + "'");
        if (it->type != 'F' || it->size != 4 || it->count != 1)
            throw DecodeError(std::string("field '") + name + "' is " + it->type +
                              std::to_string(it->size) + " x" + std::to_string(it->count) +
                              ", expected one float32 (F 4) as in nuScenes' radar sweeps");
        return it->offset;
    };
    const std::size_t ox = offset("x"), oy = offset("y"), oz = offset("z"), orcs = offset("rcs"),
                      ovx = offset("vx"), ovy = offset("vy");
    const auto value = [&](std::size_t point, std::size_t field_offset) {
        float v;
        std::memcpy(&v, bytes.data() + point * step + field_offset, sizeof(v));  // little-endian
        return static_cast<double>(v);
    };
    RadarScan scan;
    scan.Resize(static_cast<Eigen::Index>(points));
    scan.has_power = true;
    for (std::size_t k = 0; k < points; ++k) {
        const auto i = static_cast<Eigen::Index>(k);
        const double x = value(k, ox), y = value(k, oy);
        scan.xyz_radar.col(i) << x, y, value(k, oz);
        scan.power_db[i] = value(k, orcs);
        // The radial velocity the radar measured: the uncompensated velocity along the line of
        // sight (NaN at the origin: removed as a non-finite point).
        scan.doppler_mps[i] = (x * value(k, ovx) + y * value(k, ovy)) / std::hypot(x, y);
    }
    scan.DeriveSphericalFromXyz();
    return scan;
}

class NuScenesReader final : public DatasetReader {
  public:
    NuScenesReader(const DatasetConfig &config, const std::vector<std::string> &channels)
        : scene_(IndexNuScenesScene(config.nuscenes, channels)),
          scans_of_radar_(scene_.radars.size(), 0) {
        std::string names;
        for (const NuScenesRadar &radar : scene_.radars)
            names += (names.empty() ? "" : ", ") + radar.channel;
        source_ = config.nuscenes.dataroot + " (" + config.nuscenes.scene + ", " + names + ")";
    }

    bool Next(DatasetEvent &event) override {
        if (next_ >= scene_.sweeps.size()) return false;
        const NuScenesSweep &sweep = scene_.sweeps[next_++];
        event = DatasetEvent{};
        event.radar = sweep.radar;
        event.scan_index = scans_of_radar_[sweep.radar]++;
        event.stamp_ns = sweep.timestamp_us * kNanosPerMicro;
        try {
            event.scan = DecodeSweep(sweep.file);
        } catch (const DecodeError &e) {
            event.kind = DatasetEvent::Kind::kBadScan;
            event.problem =
                sweep.file + " (scan " + std::to_string(event.scan_index) + "): " + e.what();
            return true;
        }
        event.kind = DatasetEvent::Kind::kRadarScan;
        event.scan.stamp_ns = event.stamp_ns;
        event.scan.frame_id = scene_.radars[sweep.radar].channel;
        event.removed_nonfinite_points = RemoveNonFinitePoints(event.scan);
        return true;
    }

    [[nodiscard]] std::string source() const override { return source_; }

  private:
    NuScenesScene scene_;
    std::vector<std::size_t> scans_of_radar_;
    std::string source_;
    std::size_t next_ = 0;
};

}  // namespace

std::unique_ptr<DatasetReader> OpenNuScenesReader(const DatasetConfig &config,
                                                  const std::vector<std::string> &channels) {
    return std::make_unique<NuScenesReader>(config, channels);
}

Eigen::Isometry3d NuScenesMount(const DatasetConfig &config) {
    // T_ego_radar: nuScenes' ego frame is the rear axle's centre
    return IndexNuScenesScene(config.nuscenes, {OneNuScenesChannel(config)})
        .radars.front()
        .Mount(config.nuscenes);
}

std::vector<RadarStream> NuScenesRadars(const DatasetConfig &config) {
    std::vector<RadarStream> radars;
    for (const NuScenesRadar &r : IndexNuScenesScene(config.nuscenes, {}).radars) {
        RadarStream radar;
        radar.name = r.channel;
        radar.nuscenes_channel = r.channel;
        radar.T_base_radar = r.Mount(config.nuscenes);
        radars.push_back(radar);
    }
    return radars;
}

Trajectory LoadNuScenesEgoPoses(const DatasetConfig &config) {
    std::vector<StampedPose> stamped;
    for (const auto &[t_us, T_global_ego] : NuScenesEgoPoses(config.nuscenes))
        stamped.push_back({t_us * kNanosPerMicro, T_global_ego});
    return Trajectory(std::move(stamped));
}

}  // namespace dorado::io
