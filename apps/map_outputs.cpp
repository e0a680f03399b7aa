#include "map_outputs.hpp"

#include <algorithm>
#include <cstdio>

#include "dorado/core/time.hpp"
#include "dorado/io/atomic_file.hpp"
#include "dorado/io/point_cloud_files.hpp"
#include "dorado/io/trajectory_io.hpp"
#include "map_image.hpp"

namespace dorado::apps {
namespace {

constexpr const char *kCsvHeader =
    "t,time_doppler_ms,time_prior_ms,time_preprocess_ms,time_registration_ms,time_refinement_ms,"
    "time_map_update_ms,time_total_ms,correspondences,fitness,fallback,fallback_reason,prior,"
    "prior_substitution,local_map_points\n";

std::string Quoted(const std::string &text) {
    std::string out = "\"";
    for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
    return out + "\"";
}

// "bad fitness (rms 1.7 m)" -> "bad fitness": the reason's kind, for the counts.
std::string Kind(const std::string &reason) {
    return reason.substr(0, reason.find(" ("));
}

}  // namespace

nlohmann::json TimeStatistics(std::vector<double> values_ms) {
    if (values_ms.empty()) return nullptr;
    std::sort(values_ms.begin(), values_ms.end());
    double mean = 0.0;
    for (double t : values_ms) mean += t / static_cast<double>(values_ms.size());
    const auto at = [&](double q) {
        return values_ms[static_cast<std::size_t>(q * static_cast<double>(values_ms.size() - 1))];
    };
    return {{"mean", mean}, {"median", values_ms[values_ms.size() / 2]}, {"p95", at(0.95)}};
}

MapOutputs::MapOutputs(double output_voxel_m) : map_(output_voxel_m), csv_(kCsvHeader) {}

void MapOutputs::Add(const frontend::FrontEndResult &result) {
    const mapping::RegistrationResult &r = result.registration;
    const frontend::FrontEndTimes &t = result.times;
    map_.Add(result.static_points_world);
    covariances_.Add(result);
    positions_.push_back(result.T_world_base.translation());
    if (r.fallback) {
        ++fallbacks_;
        fallback_reasons_[Kind(r.fallback_reason)]++;
    }
    if (!result.prior_substitution.empty()) prior_substitutions_[result.prior_substitution]++;
    if (result.static_mask.size() == 0) ++unmasked_;
    const std::pair<const char *, double> stages[] = {{"doppler", t.doppler_ms},
                                                      {"prior", t.prior_ms},
                                                      {"preprocess", t.mapper.preprocess_ms},
                                                      {"registration", t.mapper.registration_ms},
                                                      {"refinement", t.mapper.refinement_ms},
                                                      {"map_update", t.mapper.map_update_ms},
                                                      {"total", t.total_ms}};
    for (const auto &[name, ms] : stages) stage_ms_[name].push_back(ms);
    char row[512];
    std::snprintf(row, sizeof(row), "%.9f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%d,%.5f,%d,",
                  NanosToSeconds(result.stamp_ns), t.doppler_ms, t.prior_ms, t.mapper.preprocess_ms,
                  t.mapper.registration_ms, t.mapper.refinement_ms, t.mapper.map_update_ms,
                  t.total_ms, r.correspondences, r.fitness_rms_m, r.fallback ? 1 : 0);
    csv_ += row + Quoted(r.fallback_reason) + ',' +
            (result.prior_first_scan ? "first scan" : mapping::ToString(result.prior_used)) + ',' +
            Quoted(result.prior_substitution) + ',' + std::to_string(r.local_map_points) + '\n';
    max_local_map_points_ = std::max(max_local_map_points_, r.local_map_points);
}

void MapOutputs::Write(const std::string &out_dir, const Trajectory &trajectory) const {
    io::WriteTum(out_dir + "/trajectory.tum", trajectory);
    const Eigen::Matrix3Xd points = map_.Points();
    io::WritePcd(out_dir + "/map.pcd", points);
    io::WritePly(out_dir + "/map.ply", points);
    WriteBirdsEyeImage(out_dir + "/map.png", points, positions_);
    io::WriteFileAtomically(out_dir + "/scans.csv", [&](std::ostream &os) { os << csv_; });
    io::WriteFileAtomically(out_dir + "/covariance.csv",
                            [&](std::ostream &os) { os << covariances_.csv(); });
}

nlohmann::json MapOutputs::Summary() const {
    nlohmann::json stages = nlohmann::json::object();
    for (const auto &[name, values] : stage_ms_) {
        if (std::string(name) != "total") stages[name] = TimeStatistics(values);
    }
    const auto total = stage_ms_.find("total");
    return {{"fallbacks", fallbacks_},
            {"fallback_reasons", fallback_reasons_},
            {"prior_substitutions_constvel", prior_substitutions_},
            {"scans_without_mask", unmasked_},
            {"time_per_scan_ms",
             TimeStatistics(total == stage_ms_.end() ? std::vector<double>{} : total->second)},
            {"time_per_stage_ms", stages},
            {"map_points", map_.size()},
            {"local_map_points_max", max_local_map_points_}};
}

double MapOutputs::mean_time_ms() const {
    const auto total = stage_ms_.find("total");
    if (total == stage_ms_.end() || total->second.empty()) return 0.0;
    double mean = 0.0;
    for (double t : total->second) mean += t / static_cast<double>(total->second.size());
    return mean;
}

}  // namespace dorado::apps
