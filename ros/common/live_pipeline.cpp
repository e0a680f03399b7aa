#include "live_pipeline.hpp"

#include <cstdarg>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <nlohmann/json.hpp>

namespace dorado::ros_node {
namespace {

// The calling thread's CPU time [ms]: what a scan costs the worker, whatever else runs.
double ThreadCpuMs() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

}  // namespace

LivePipeline::LivePipeline(NodeSettings settings, LiveSink &sink, std::string node_name)
    : settings_(std::move(settings)),
      sink_(sink),
      name_(std::move(node_name)),
      front_end_(settings_.front_end, settings_.dataset.extrinsics, settings_.dataset.vehicle),
      stamps_(settings_.gaps),
      T_world_base_initial_(settings_.T_world_child_initial * settings_.T_base_child.inverse()) {
    front_end_.Reset(T_world_base_initial_);
    if (settings_.front_end.run_mapper && settings_.loop_closure.enabled)
        loops_ = std::make_unique<LoopWorker>(settings_.loop_closure);
    last_report_ = last_local_map_ = Clock::now();
    worker_ = std::thread([this] { Work(); });
}

LivePipeline::~LivePipeline() {
    Shutdown(false);
}

std::string LivePipeline::MapperDescription() const {
    if (!settings_.front_end.run_mapper) return "; mapper off";
    return std::string(loops_ ? "; mapper and loop closure on" : "; mapper on") + ", prior " +
           mapping::ToString(settings_.front_end.prior);
}

void LivePipeline::Log(LogLevel level, const char *format, ...) {
    char text[2048];
    va_list args;
    va_start(args, format);
    std::vsnprintf(text, sizeof(text), format, args);
    va_end(args);
    sink_.Log(level, name_ + ": " + text);
}

bool LivePipeline::CountWarning(const std::string &cause, const std::string &detail) {
    std::lock_guard<std::mutex> lock(mutex_);
    return warnings_.Count(cause, detail);
}

void LivePipeline::Increment(long long &count) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++count;
}

LiveCounts LivePipeline::counts() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return counts_;
}

void LivePipeline::OnCloud(LiveCloud cloud) {
    if (cloud.stamp_ns == 0) cloud.stamp_ns = sink_.NowNs();  // unstamped: stamped at arrival
    std::lock_guard<std::mutex> lock(mutex_);
    if (stop_) return;
    ++counts_.received;
    if (static_cast<int>(queue_.size()) >= settings_.queue_size) {
        const LiveCloud &oldest = queue_.front();
        Drop("late (processing behind)",
             "scan stamped " + std::to_string(static_cast<double>(oldest.stamp_ns) * 1e-9) +
                 " s overtaken while " + std::to_string(queue_.size()) +
                 " scans waited (queue_size " + std::to_string(settings_.queue_size) + ")");
        queue_.pop_front();
        ++late_drops_;
    }
    queue_.push_back(std::move(cloud));
    wake_.notify_all();
}

void LivePipeline::OnUnreadable(const std::string &error) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stop_) return;
    ++counts_.received;
    if (faults_.Count("unreadable message", error))
        Log(LogLevel::kError,
            "topic %s: a message that does not deserialize: %s. Every message like it is dropped "
            "(counted, summarised)",
            settings_.input_topic.c_str(), error.c_str());
}

void LivePipeline::OnImu(const ImuSample &sample) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (sample.stamp_ns <= last_imu_stamp_ns_) return;  // old or repeated: the window has it
    last_imu_stamp_ns_ = sample.stamp_ns;
    imu_.push_back(sample);
    wake_.notify_all();
}

void LivePipeline::OnPublishers(const std::string &topic, int count) {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::string cause = count == 0 ? "publisher lost" : "publisher back";
    if (warnings_.Count(cause, topic))
        Log(count == 0 ? LogLevel::kWarn : LogLevel::kInfo,
            count == 0 ? "%s: its last publisher went away; waiting for it (further losses are "
                         "counted and summarised)"
                       : "%s: a publisher is back (%d)",
            topic.c_str(), count);
}

void LivePipeline::Work() {
    while (true) {
        LiveCloud cloud;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            wake_.wait(lock, [this] { return stop_ || !queue_.empty(); });
            if (stop_) return;
            cloud = std::move(queue_.front());
            queue_.pop_front();
        }
        Handle(cloud);
        ReportPeriodically();
    }
}

// Caller holds mutex_ (or is the worker, which owns the stamps and the front end).
void LivePipeline::Drop(const std::string &cause, const std::string &detail) {
    if (faults_.Count(cause, detail))
        Log(LogLevel::kWarn,
            "%s: dropped a scan on %s (%s); further ones are counted and summarised every %.0f s",
            cause.c_str(), settings_.input_topic.c_str(), detail.c_str(),
            settings_.report_period_s);
}

void LivePipeline::Handle(const LiveCloud &cloud) {
    const double cpu_start_ms = ThreadCpuMs();
    const int64_t stamp_ns = cloud.stamp_ns;
    const StampVerdict verdict = stamps_.Check(stamp_ns);
    if (verdict != StampVerdict::kAccept) {
        std::lock_guard<std::mutex> lock(mutex_);
        Drop(verdict == StampVerdict::kDuplicate ? "duplicate stamp" : "out of order",
             "stamp " + std::to_string(static_cast<double>(cloud.stamp_ns) * 1e-9) +
                 " s is not after the last scan's");
        return;
    }
    RadarScan scan;
    if (!Decode(cloud, scan)) return;
    scan.stamp_ns = stamp_ns;
    scan.frame_id = cloud.frame_id;
    io::RemoveNonFinitePoints(scan);

    bool dropped_since_last;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        dropped_since_last = late_drops_ != late_drops_seen_;
        late_drops_seen_ = late_drops_;
    }
    const GapVerdict gap = stamps_.Accept(stamp_ns, dropped_since_last);
    if (gap == GapVerdict::kReset) {
        Increment(counts_.resets);
        const Eigen::Isometry3d T_world_base =
            front_end_.trajectory().empty() ? T_world_base_initial_
                                            : front_end_.trajectory().poses().back().T_world_body;
        Log(LogLevel::kWarn,
            "%.2f s without a scan on %s (max_gap_s %.2f): starting over at the last pose (a new "
            "map, no prior)",
            stamps_.last_interval_s(), settings_.input_topic.c_str(), settings_.gaps.max_gap_s);
        PublishWritten(front_end_.Reset(T_world_base));
    } else if (gap == GapVerdict::kIntegrate &&
               CountWarning("gap integrated over", std::to_string(stamps_.last_interval_s()))) {
        Log(LogLevel::kWarn,
            "%.2f s since the previous scan (ordinary %.2f s): integrated over the real "
            "interval; further gaps are summarised",
            stamps_.last_interval_s(), stamps_.ordinary_interval_s());
    }
    if (settings_.needs_imu) WatchImu(FeedImu(stamp_ns), stamp_ns);

    const frontend::FrontEndResult result = front_end_.Process(scan);
    if (!result.accepted) {
        std::lock_guard<std::mutex> lock(mutex_);
        Drop("rejected by the front end", result.skip_reason);
        return;
    }
    Increment(counts_.processed);
    ReportPrior(result);
    if (gap == GapVerdict::kReset) pose_covariance_.Reset();  // not honest across a reset
    pose_covariance_.Step(result.T_world_base_odometry, result.twist_base.covariance, result.dt_s);
    Publish(stamp_ns, scan, result);
    latency_.Add(MillisecondsSince(cloud.arrival));
    front_end_time_.Add(result.times.total_ms);
    worker_cpu_.Add(ThreadCpuMs() - cpu_start_ms);
    if (settings_.verbose) {
        const auto &ego = result.odometry.ego;
        Log(LogLevel::kInfo,
            "scan %.3f: %d / %d inliers, v_radar (%.3f %.3f %.3f) m/s, omega (%.4f %.4f %.4f) "
            "rad/s, %.1f ms",
            static_cast<double>(stamp_ns) * 1e-9, ego.inliers, static_cast<int>(scan.size()),
            ego.v_radar_mps.x(), ego.v_radar_mps.y(), ego.v_radar_mps.z(),
            result.twist_base.omega_base_radps.x(), result.twist_base.omega_base_radps.y(),
            result.twist_base.omega_base_radps.z(), result.times.total_ms);
    }
}

bool LivePipeline::Decode(const LiveCloud &cloud, RadarScan &scan) {
    try {
        scan = io::DecodePointCloud(cloud.view, settings_.dataset.fields);
        return true;
    } catch (const io::DecodeError &e) {
        // One clear error per cause (a wrong field map fails every message the same way).
        std::lock_guard<std::mutex> lock(mutex_);
        if (faults_.Count(std::string("undecodable: ") + e.what(), e.what()))
            Log(LogLevel::kError,
                "topic %s: %s; its fields: %s. Every scan like it is dropped (counted, "
                "summarised); fix `fields` in the dataset YAML (%s)",
                settings_.input_topic.c_str(), e.what(),
                io::DescribeFields(cloud.view.fields).c_str(),
                settings_.dataset.config_path.empty() ? "parameter config"
                                                      : settings_.dataset.config_path.c_str());
        return false;
    }
}

// Hands the front end the IMU samples up to the scan, waiting a little for the IMU to catch up
// (not while it is known to be stalled). Returns false when it has not reached the scan's stamp.
bool LivePipeline::FeedImu(int64_t stamp_ns) {
    std::vector<ImuSample> samples;
    bool current = false;
    {
        std::unique_lock<std::mutex> lock(mutex_);
        if (!imu_stalled_) {
            wake_.wait_for(lock, std::chrono::duration<double>(settings_.imu_wait_s),
                           [&] { return stop_ || last_imu_stamp_ns_ >= stamp_ns; });
        }
        current = last_imu_stamp_ns_ >= stamp_ns;
        while (!imu_.empty() && imu_.front().stamp_ns <= stamp_ns) {
            samples.push_back(imu_.front());
            imu_.pop_front();
        }
    }
    for (const ImuSample &s : samples) front_end_.AddImu(s);
    return current;
}

// An IMU that stalls while the prior needs it: the Doppler prior stands in, said once (and once
// more when the IMU is back).
void LivePipeline::WatchImu(bool imu_current, int64_t stamp_ns) {
    const bool prior_needs_imu =
        settings_.front_end.run_mapper && mapping::NeedsImu(settings_.front_end.prior);
    if (!imu_current && !imu_stalled_) {
        imu_stalled_ = true;
        if (prior_needs_imu) front_end_.SetPrior(mapping::PriorKind::kDoppler);
        int64_t last_ns;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            last_ns = last_imu_stamp_ns_;
            warnings_.Count("imu stalled", settings_.imu_topic);
        }
        const std::string since =
            last_ns == 0
                ? "no sample yet"
                : "last sample " + std::to_string(static_cast<double>(stamp_ns - last_ns) * 1e-9) +
                      " s before the scan";
        Log(LogLevel::kWarn, "%s has stalled (%s): %s until it resumes",
            settings_.imu_topic.c_str(), since.c_str(),
            prior_needs_imu ? "the doppler prior stands in" : "the odometry falls back");
    } else if (imu_current && imu_stalled_) {
        imu_stalled_ = false;
        if (prior_needs_imu) front_end_.SetPrior(settings_.front_end.prior);
        const std::string again =
            prior_needs_imu ? ": the " + std::string(mapping::ToString(settings_.front_end.prior)) +
                                  " prior again"
                            : "";
        Log(LogLevel::kInfo, "%s is back%s", settings_.imu_topic.c_str(), again.c_str());
    }
}

// The front end's own substitutions (no valid Doppler velocity: constvel) and odometry
// fallbacks: the first of each logged, the rest summarised.
void LivePipeline::ReportPrior(const frontend::FrontEndResult &result) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (result.prior_substitution != frontend::PriorSubstitution::kNone &&
        !result.prior_first_scan) {
        std::string why = frontend::SubstitutionKey(frontend::SubstitutionCauseOf(result));
        if (!result.prior_substitution_detail.empty())
            why += ": " + result.prior_substitution_detail;
        if (warnings_.Count("prior substituted", why))
            Log(LogLevel::kWarn,
                "the %s prior could not be built (%s): the %s prior stood in (further ones are "
                "summarised)",
                mapping::ToString(result.prior_requested), why.c_str(),
                mapping::ToString(result.prior_used));
    }
    if (result.odometry.used_fallback &&
        warnings_.Count("odometry fallback", result.odometry.fallback_reason))
        Log(LogLevel::kWarn, "odometry fell back: %s (further ones are summarised)",
            result.odometry.fallback_reason.c_str());
}

void LivePipeline::ReportPeriodically() {
    if (std::chrono::duration<double>(Clock::now() - last_report_).count() <
        settings_.report_period_s)
        return;
    last_report_ = Clock::now();
    std::lock_guard<std::mutex> lock(mutex_);
    const std::string dropped = faults_.TakeRecent(), warned = warnings_.TakeRecent();
    if (!dropped.empty())
        Log(LogLevel::kWarn, "scans dropped in the last %.0f s: %s (%lld since the start)",
            settings_.report_period_s, dropped.c_str(), faults_.total());
    if (!warned.empty())
        Log(LogLevel::kWarn, "scans used despite a fault in the last %.0f s: %s",
            settings_.report_period_s, warned.c_str());
}

void LivePipeline::Shutdown(bool finish) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (shut_down_) return;
        shut_down_ = stop_ = true;
        for (std::size_t i = 0; i < queue_.size(); ++i)
            faults_.Count("not processed at shutdown", "still queued");
        wake_.notify_all();
    }
    if (worker_.joinable()) worker_.join();
    if (loops_) loops_->Stop();
    if (finish) PublishWritten(front_end_.Finish());
    std::string dropped;
    for (const auto &[cause, count] : faults_.totals())
        dropped += (dropped.empty() ? "" : ", ") + cause + " " + std::to_string(count);
    // stderr: the ROS logging may be down by now.
    std::fprintf(stderr,
                 "%s: %lld scans received, %lld processed, %lld published, %lld resets; dropped: "
                 "%s; latency arrival->publish median %.2f ms, p95 %.2f ms (the front end's own "
                 "time median %.2f ms; the worker's CPU time per scan median %.2f ms)\n",
                 name_.c_str(), counts_.received, counts_.processed, counts_.published,
                 counts_.resets, dropped.empty() ? "none" : dropped.c_str(), latency_.Quantile(0.5),
                 latency_.Quantile(0.95), front_end_time_.Quantile(0.5), worker_cpu_.Quantile(0.5));
    WriteSummary();
}

void LivePipeline::WriteSummary() const {
    if (settings_.summary_file.empty()) return;
    nlohmann::json summary = {
        {"received", counts_.received},
        {"processed", counts_.processed},
        {"published", counts_.published},
        {"resets", counts_.resets},
        {"dropped", faults_.totals()},
        {"dropped_first", faults_.first_details()},
        {"warnings", warnings_.totals()},
        {"latency_ms",
         {{"count", latency_.size()},
          {"median", latency_.Quantile(0.5)},
          {"p95", latency_.Quantile(0.95)}}},
        {"front_end_ms",
         {{"median", front_end_time_.Quantile(0.5)}, {"p95", front_end_time_.Quantile(0.95)}}},
        {"worker_cpu_ms",
         {{"median", worker_cpu_.Quantile(0.5)}, {"p95", worker_cpu_.Quantile(0.95)}}}};
    std::ofstream out(settings_.summary_file);
    out << summary.dump(2) << '\n';
    if (!out)
        std::fprintf(stderr, "%s: error: cannot write %s\n", name_.c_str(),
                     settings_.summary_file.c_str());
}

}  // namespace dorado::ros_node
