#include "map_outputs.hpp"

#include <algorithm>
#include <cstdio>

#include "dorado/core/time.hpp"
#include "dorado/io/atomic_file.hpp"
#include "dorado/io/csv_text.hpp"
#include "dorado/io/point_cloud_files.hpp"
#include "dorado/io/trajectory_io.hpp"
#include "map_image.hpp"
#include "scan_loop.hpp"

namespace dorado::apps {
namespace {

constexpr const char *kCsvHeader =
    "t,time_doppler_ms,time_prior_ms,time_preprocess_ms,time_registration_ms,time_refinement_ms,"
    "time_map_update_ms,time_total_ms,correspondences,fitness,fallback,fallback_reason,prior,"
    "prior_substitution,local_map_points,s_x_online_m,sigma_s_x_online_m,yaw_calibration,"
    "mover_points_dropped,map_points_dropped,prior_mahalanobis_squared,registration_weight\n";

// "bad fitness (rms 1.7 m)": the cause and its numbers, for scans.csv.
std::string Reason(const mapping::RegistrationResult &r) {
    std::string reason = mapping::ToString(r.fallback_cause);
    if (!r.fallback_detail.empty()) reason += " (" + r.fallback_detail + ")";
    return reason;
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

nlohmann::json MapRunSummary(const std::string &dataset_name,
                             const frontend::FrontEndConfig &config, const std::string &stopped) {
    return {{"dataset", dataset_name},
            {"prior", mapping::ToString(config.prior)},
            {"mask", config.use_mask},
            {"smoother_lag_s", config.mapper.smoother.lag_s},
            {"method", mapping::ToString(config.mapper.method)},
            {"stopped_early", stopped.empty() ? nlohmann::json() : nlohmann::json(stopped)}};
}

MapOutputs::MapOutputs(double map_cell_m) : map_cell_m_(map_cell_m), csv_(kCsvHeader) {}

Eigen::Matrix3Xd MapOutputs::MapPoints(const std::vector<Eigen::Isometry3d> *corrections) const {
    Eigen::Matrix3Xd points(3, static_cast<Eigen::Index>(map_point_count_));
    Eigen::Index n = 0;
    for (const auto &[key, cell] : map_points_world_)
        for (const MapPoint &point : cell) {
            const Eigen::Vector3d p_world = point.p_world.cast<double>();
            points.col(n++) = corrections != nullptr && point.written_index < corrections->size()
                                  ? Eigen::Vector3d((*corrections)[point.written_index] * p_world)
                                  : p_world;
        }
    return points;
}

void MapOutputs::Add(const frontend::FrontEndResult &result) {
    const mapping::RegistrationResult &r = result.registration;
    const frontend::FrontEndTimes &t = result.times;
    for (const mapping::VoxelKey &key : r.map_cells_dropped) {
        const auto it = map_points_world_.find(key);
        if (it == map_points_world_.end()) continue;
        map_point_count_ -= it->second.size();
        map_points_world_.erase(it);
    }
    AddWritten(r.written);
    if (first_stamp_ns_ < 0) first_stamp_ns_ = result.stamp_ns;
    if (r.fallback()) {
        ++fallbacks_;
        fallback_reasons_[r.fallback_cause]++;
        // The young map (its first seconds) apart: a small map registers worse.
        const double since_start_s = NanosToSeconds(result.stamp_ns - first_stamp_ns_);
        if (since_start_s < kYoungMapS) young_map_fallback_reasons_[r.fallback_cause]++;
        const auto bin = static_cast<std::size_t>(std::max(0.0, since_start_s / kYoungMapS));
        if (fallbacks_by_time_.size() <= bin) fallbacks_by_time_.resize(bin + 1, 0);
        ++fallbacks_by_time_[bin];
    }
    ++scans_;
    const frontend::SubstitutionCause substitution = frontend::SubstitutionCauseOf(result);
    if (result.prior_substitution != frontend::PriorSubstitution::kNone)
        prior_substitutions_[substitution]++;
    if (result.static_mask.size() == 0) ++unmasked_;
    predictions_[result.odometry.ego.prediction]++;
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
                  t.total_ms, r.correspondences, r.fitness_rms_m, r.fallback() ? 1 : 0);
    csv_ += row + io::CsvQuoted(Reason(r)) + ',' +
            (result.prior_first_scan ? "first scan" : mapping::ToString(result.prior_used)) + ',' +
            io::CsvQuoted(frontend::SubstitutionKey(substitution)) + ',' +
            std::to_string(r.local_map_points) + ',';
    // The online yaw lever after this scan (empty when the calibration is off).
    const odometry::YawCalibrationStep &yaw = result.yaw_calibration;
    if (yaw.status != odometry::YawCalibrationStatus::kDisabled) {
        std::snprintf(row, sizeof(row), "%.5f,%.5f,", yaw.s_x_m, yaw.sigma_s_x_m);
        csv_ += row;
        yaw_calibration_ = yaw;
        yaw_calibration_counts_[yaw.status]++;
    } else {
        csv_ += ",,";
    }
    csv_ += std::string(odometry::ToString(yaw.status)) + ',' +
            std::to_string(r.mover_points_dropped()) + ',' + std::to_string(r.map_points_dropped);
    std::snprintf(row, sizeof(row), ",%.4g,%.4f\n", r.prior_mahalanobis_squared,
                  r.registration_weight);
    csv_ += row;
    mover_points_dropped_ += r.mover_points_dropped();
    map_points_dropped_ += r.map_points_dropped;
    max_local_map_points_ = std::max(max_local_map_points_, r.local_map_points);
}

void MapOutputs::AddWritten(const std::vector<mapping::WrittenPose> &written) {
    for (const mapping::WrittenPose &w : written) {
        const Eigen::Matrix3Xd &added = w.map_points_added_world;
        for (Eigen::Index i = 0; i < added.cols(); ++i) {
            map_points_world_[mapping::VoxelKeyOf(added.col(i), map_cell_m_)].push_back(
                {added.col(i).cast<float>(), written_});
            ++map_point_count_;
        }
        covariances_.Add(w);
        positions_.push_back(w.T_world_base.translation());
        ++written_;
    }
}

void MapOutputs::Write(const std::string &out_dir, const Trajectory &trajectory,
                       const std::vector<Eigen::Vector3d> &reference_world,
                       const MapCorrection *correction) const {
    io::WriteTum(out_dir + "/trajectory.tum", trajectory);
    const Eigen::Matrix3Xd points = MapPoints(correction ? &correction->corrections : nullptr);
    io::WritePcd(out_dir + "/map.pcd", points);
    io::WritePly(out_dir + "/map.ply", points);
    std::vector<Eigen::Vector3d> positions = positions_;
    if (correction != nullptr)
        for (std::size_t i = 0; i < positions.size() && i < correction->corrections.size(); ++i)
            positions[i] = correction->corrections[i] * positions[i];
    WriteBirdsEyeImage(out_dir + "/map.png", points, positions, reference_world,
                       correction ? correction->loops_world : std::vector<LoopEdge>{});
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
            {"fallback_rate", scans_ > 0 ? static_cast<double>(fallbacks_) / scans_ : 0.0},
            {"fallback_reasons", CountsByKey(fallback_reasons_)},
            {"fallback_reasons_first_5s", CountsByKey(young_map_fallback_reasons_)},
            {"fallbacks_per_5s", fallbacks_by_time_},
            {"prior_substitutions_constvel",
             CountsByKey(prior_substitutions_, frontend::SubstitutionKey)},
            {"scans_without_mask", unmasked_},
            {"velocity_prediction", CountsByKey(predictions_)},
            {"mover_points_dropped", mover_points_dropped_},
            {"map_points_dropped", map_points_dropped_},
            {"time_per_scan_ms",
             TimeStatistics(total == stage_ms_.end() ? std::vector<double>{} : total->second)},
            {"time_per_stage_ms", stages},
            {"online_calibration",
             yaw_calibration_counts_.empty()
                 ? nlohmann::json()
                 : nlohmann::json{{"s_x_m", yaw_calibration_.s_x_m},
                                  {"sigma_s_x_m", yaw_calibration_.sigma_s_x_m},
                                  {"scans_by_status", CountsByKey(yaw_calibration_counts_)}}},
            {"map_points", map_point_count_},
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
