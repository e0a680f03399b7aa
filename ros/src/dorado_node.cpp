#include "dorado_node.hpp"

#include <nav_msgs/Odometry.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "dorado/core/time.hpp"
#include "dorado/io/pointcloud_decoder.hpp"
#include "ros_messages.hpp"

namespace dorado::ros_node {

DoradoNode::DoradoNode(ros::NodeHandle &node, NodeSettings settings)
    : settings_(std::move(settings)),
      front_end_(settings_.front_end, settings_.dataset.extrinsics, settings_.dataset.vehicle),
      stamps_(settings_.gaps),
      T_world_base_initial_(settings_.T_world_child_initial * settings_.T_base_child.inverse()) {
    front_end_.Reset(T_world_base_initial_);
    odom_pub_ = node.advertise<nav_msgs::Odometry>("/doppler_odom", 100);
    if (settings_.front_end.run_mapper) {
        map_odom_pub_ = node.advertise<nav_msgs::Odometry>("/dorado/map_odom", 100);
        smoothed_odom_pub_ = node.advertise<nav_msgs::Odometry>("/dorado/smoothed_odom", 100);
        static_pub_ = node.advertise<sensor_msgs::PointCloud2>("/dorado/static_points", 5);
        dynamic_pub_ = node.advertise<sensor_msgs::PointCloud2>("/dorado/dynamic_points", 5);
        local_map_pub_ = node.advertise<sensor_msgs::PointCloud2>("/dorado/local_map", 1, true);
    }
    if (settings_.front_end.run_mapper && settings_.loop_closure.enabled)
        loops_ = std::make_unique<LoopWorker>(settings_.loop_closure);
    last_report_ = last_local_map_ = Clock::now();
    worker_ = std::thread([this] { Work(); });
    // The ROS queue is long and the callback cheap: the node, not roscpp, decides what is dropped.
    cloud_sub_ = node.subscribe(settings_.input_topic, 100, &DoradoNode::OnCloud, this,
                                ros::TransportHints().tcpNoDelay());
    if (settings_.needs_imu)
        imu_sub_ = node.subscribe(settings_.imu_topic, 1000, &DoradoNode::OnImu, this,
                                  ros::TransportHints().tcpNoDelay());
    ROS_INFO("dorado_ros: %s; radar %s -> /doppler_odom and TF %s -> %s%s%s%s",
             settings_.description.c_str(), settings_.input_topic.c_str(),
             settings_.tf_from_frame.c_str(), settings_.tf_to_frame.c_str(),
             settings_.front_end.run_mapper
                 ? (loops_ ? "; mapper and loop closure on, prior " : "; mapper on, prior ")
                 : "; mapper off",
             settings_.front_end.run_mapper ? mapping::ToString(settings_.front_end.prior) : "",
             settings_.needs_imu ? ("; IMU " + settings_.imu_topic).c_str() : "");
}

DoradoNode::~DoradoNode() {
    Shutdown();
}

void DoradoNode::OnCloud(const sensor_msgs::PointCloud2ConstPtr &msg) {
    const Pending pending{msg, Clock::now()};
    std::lock_guard<std::mutex> lock(mutex_);
    if (stop_) return;
    ++received_;
    if (static_cast<int>(queue_.size()) >= settings_.queue_size) {
        const Pending &oldest = queue_.front();
        Drop("late (processing behind)",
             "scan stamped " + std::to_string(oldest.msg->header.stamp.toSec()) +
                 " s overtaken while " + std::to_string(queue_.size()) +
                 " scans waited (queue_size " + std::to_string(settings_.queue_size) + ")");
        queue_.pop_front();
        ++late_drops_;
    }
    queue_.push_back(pending);
    wake_.notify_all();
}

void DoradoNode::OnImu(const sensor_msgs::ImuConstPtr &msg) {
    ImuSample sample;
    sample.stamp_ns = static_cast<int64_t>(msg->header.stamp.toNSec());
    sample.omega_imu_radps << msg->angular_velocity.x, msg->angular_velocity.y,
        msg->angular_velocity.z;
    sample.accel_imu_mps2 << msg->linear_acceleration.x, msg->linear_acceleration.y,
        msg->linear_acceleration.z;
    std::lock_guard<std::mutex> lock(mutex_);
    if (sample.stamp_ns <= last_imu_stamp_ns_) return;  // old or repeated: the window has it
    last_imu_stamp_ns_ = sample.stamp_ns;
    imu_.push_back(sample);
    wake_.notify_all();
}

void DoradoNode::Work() {
    while (true) {
        Pending pending;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            wake_.wait(lock, [this] { return stop_ || !queue_.empty(); });
            if (stop_) return;
            pending = queue_.front();
            queue_.pop_front();
        }
        Handle(pending);
        ReportPeriodically();
    }
}

// Caller holds mutex_ (or is the worker, which owns the stamps and the front end).
void DoradoNode::Drop(const std::string &cause, const std::string &detail) {
    if (faults_.Count(cause, detail))
        ROS_WARN(
            "dorado_ros: %s: dropped a scan on %s (%s); further ones are counted and "
            "summarised every %.0f s",
            cause.c_str(), settings_.input_topic.c_str(), detail.c_str(),
            settings_.report_period_s);
}

void DoradoNode::Handle(const Pending &pending) {
    const sensor_msgs::PointCloud2 &msg = *pending.msg;
    const int64_t stamp_ns = static_cast<int64_t>(
        msg.header.stamp.isZero() ? ros::Time::now().toNSec() : msg.header.stamp.toNSec());
    const StampVerdict verdict = stamps_.Check(stamp_ns);
    if (verdict != StampVerdict::kAccept) {
        std::lock_guard<std::mutex> lock(mutex_);
        Drop(verdict == StampVerdict::kDuplicate ? "duplicate stamp" : "out of order",
             "stamp " + std::to_string(msg.header.stamp.toSec()) +
                 " s is not after the last scan's");
        return;
    }
    RadarScan scan;
    if (!Decode(msg, scan)) return;
    scan.stamp_ns = stamp_ns;
    scan.frame_id = msg.header.frame_id;
    io::RemoveNonFinitePoints(scan);

    bool dropped_since_last;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        dropped_since_last = late_drops_ != late_drops_seen_;
        late_drops_seen_ = late_drops_;
    }
    const GapVerdict gap = stamps_.Accept(stamp_ns, dropped_since_last);
    if (gap == GapVerdict::kReset) {
        ++resets_;
        const Eigen::Isometry3d T_world_base =
            front_end_.trajectory().empty() ? T_world_base_initial_
                                            : front_end_.trajectory().poses().back().T_world_body;
        ROS_WARN(
            "dorado_ros: %.2f s without a scan on %s (max_gap_s %.2f): starting over at the "
            "last pose (a new map, no prior)",
            stamps_.last_interval_s(), settings_.input_topic.c_str(), settings_.gaps.max_gap_s);
        PublishWritten(front_end_.Reset(T_world_base));
    } else if (gap == GapVerdict::kIntegrate &&
               warnings_.Count("gap integrated over", std::to_string(stamps_.last_interval_s()))) {
        ROS_WARN(
            "dorado_ros: %.2f s since the previous scan (ordinary %.2f s): integrated over "
            "the real interval; further gaps are summarised",
            stamps_.last_interval_s(), stamps_.ordinary_interval_s());
    }
    if (settings_.needs_imu) WatchImu(FeedImu(stamp_ns), stamp_ns);

    const frontend::FrontEndResult result = front_end_.Process(scan);
    if (!result.accepted) {
        std::lock_guard<std::mutex> lock(mutex_);
        Drop("rejected by the front end", result.skip_reason);
        return;
    }
    ++processed_;
    ReportPrior(result);
    if (gap == GapVerdict::kReset) pose_covariance_.Reset();  // not honest across a reset
    pose_covariance_.Step(result.T_world_base_odometry, result.twist_base.covariance, result.dt_s);
    Publish(msg.header, scan, result);
    latency_.Add(MillisecondsSince(pending.arrival));
    if (settings_.verbose) {
        const auto &ego = result.odometry.ego;
        ROS_INFO(
            "dorado_ros: scan %.3f: %d / %d inliers, v_radar (%.3f %.3f %.3f) m/s, omega "
            "(%.4f %.4f %.4f) rad/s, %.1f ms",
            msg.header.stamp.toSec(), ego.inliers, static_cast<int>(scan.size()),
            ego.v_radar_mps.x(), ego.v_radar_mps.y(), ego.v_radar_mps.z(),
            result.twist_base.omega_base_radps.x(), result.twist_base.omega_base_radps.y(),
            result.twist_base.omega_base_radps.z(), result.times.total_ms);
    }
}

bool DoradoNode::Decode(const sensor_msgs::PointCloud2 &msg, RadarScan &scan) {
    try {
        scan = io::DecodePointCloud(io::ViewOf(msg), settings_.dataset.fields);
        return true;
    } catch (const io::DecodeError &e) {
        // One clear error per cause (a wrong field map fails every message the same way).
        std::lock_guard<std::mutex> lock(mutex_);
        if (faults_.Count(std::string("undecodable: ") + e.what(), e.what()))
            ROS_ERROR(
                "dorado_ros: topic %s: %s; its fields: %s. Every scan like it is dropped "
                "(counted, summarised); fix `fields` in the dataset YAML (%s)",
                settings_.input_topic.c_str(), e.what(),
                io::DescribeFields(io::ViewOf(msg).fields).c_str(),
                settings_.dataset.config_path.empty() ? "parameter config"
                                                      : settings_.dataset.config_path.c_str());
        return false;
    }
}

// Hands the front end the IMU samples up to the scan, waiting a little for the IMU to catch up
// (not while it is known to be stalled). Returns false when it has not reached the scan's stamp.
bool DoradoNode::FeedImu(int64_t stamp_ns) {
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
void DoradoNode::WatchImu(bool imu_current, int64_t stamp_ns) {
    const bool prior_needs_imu =
        settings_.front_end.run_mapper && mapping::NeedsImu(settings_.front_end.prior);
    if (!imu_current && !imu_stalled_) {
        imu_stalled_ = true;
        if (prior_needs_imu) front_end_.SetPrior(mapping::PriorKind::kDoppler);
        int64_t last_ns;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            last_ns = last_imu_stamp_ns_;
        }
        warnings_.Count("imu stalled", settings_.imu_topic);
        ROS_WARN(
            "dorado_ros: %s has stalled (%s): %s until it resumes", settings_.imu_topic.c_str(),
            last_ns == 0
                ? "no sample yet"
                : ("last sample " + std::to_string(static_cast<double>(stamp_ns - last_ns) * 1e-9) +
                   " s before the scan")
                      .c_str(),
            prior_needs_imu ? "the doppler prior stands in" : "the odometry falls back");
    } else if (imu_current && imu_stalled_) {
        imu_stalled_ = false;
        if (prior_needs_imu) front_end_.SetPrior(settings_.front_end.prior);
        ROS_INFO("dorado_ros: %s is back%s", settings_.imu_topic.c_str(),
                 prior_needs_imu
                     ? (": the " + std::string(mapping::ToString(settings_.front_end.prior)) +
                        " prior again")
                           .c_str()
                     : "");
    }
}

// The front end's own substitutions (no valid Doppler velocity: constvel) and odometry
// fallbacks: the first of each logged, the rest summarised.
void DoradoNode::ReportPrior(const frontend::FrontEndResult &result) {
    if (result.prior_substitution != frontend::PriorSubstitution::kNone &&
        !result.prior_first_scan) {
        std::string why = frontend::SubstitutionKey(frontend::SubstitutionCauseOf(result));
        if (!result.prior_substitution_detail.empty())
            why += ": " + result.prior_substitution_detail;
        if (warnings_.Count("prior substituted", why))
            ROS_WARN(
                "dorado_ros: the %s prior could not be built (%s): the %s prior stood in "
                "(further ones are summarised)",
                mapping::ToString(result.prior_requested), why.c_str(),
                mapping::ToString(result.prior_used));
    }
    if (result.odometry.used_fallback &&
        warnings_.Count("odometry fallback", result.odometry.fallback_reason))
        ROS_WARN("dorado_ros: odometry fell back: %s (further ones are summarised)",
                 result.odometry.fallback_reason.c_str());
}

void DoradoNode::ReportPeriodically() {
    if (std::chrono::duration<double>(Clock::now() - last_report_).count() <
        settings_.report_period_s)
        return;
    last_report_ = Clock::now();
    std::lock_guard<std::mutex> lock(mutex_);
    const std::string dropped = faults_.TakeRecent(), warned = warnings_.TakeRecent();
    if (!dropped.empty())
        ROS_WARN("dorado_ros: scans dropped in the last %.0f s: %s (%lld since the start)",
                 settings_.report_period_s, dropped.c_str(), faults_.total());
    if (!warned.empty())
        ROS_WARN("dorado_ros: scans used despite a fault in the last %.0f s: %s",
                 settings_.report_period_s, warned.c_str());
}

void DoradoNode::Shutdown() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (stop_) return;
        stop_ = true;
        for (std::size_t i = 0; i < queue_.size(); ++i)
            faults_.Count("not processed at shutdown", "still queued");
        wake_.notify_all();
    }
    if (worker_.joinable()) worker_.join();
    if (loops_) loops_->Stop();
    cloud_sub_.shutdown();
    imu_sub_.shutdown();
    std::string dropped;
    for (const auto &[cause, count] : faults_.totals())
        dropped += (dropped.empty() ? "" : ", ") + cause + " " + std::to_string(count);
    // stderr as well as rosout: this is printed after ros::shutdown.
    std::fprintf(stderr,
                 "dorado_ros: %lld scans received, %lld processed, %lld published, %lld resets; "
                 "dropped: %s; latency arrival->publish median %.2f ms, p95 %.2f ms\n",
                 received_, processed_, published_, resets_,
                 dropped.empty() ? "none" : dropped.c_str(), latency_.Quantile(0.5),
                 latency_.Quantile(0.95));
    WriteSummary();
}

void DoradoNode::WriteSummary() const {
    if (settings_.summary_file.empty()) return;
    nlohmann::json summary = {{"received", received_},
                              {"processed", processed_},
                              {"published", published_},
                              {"resets", resets_},
                              {"dropped", faults_.totals()},
                              {"dropped_first", faults_.first_details()},
                              {"warnings", warnings_.totals()},
                              {"latency_ms",
                               {{"count", latency_.size()},
                                {"median", latency_.Quantile(0.5)},
                                {"p95", latency_.Quantile(0.95)}}}};
    std::ofstream out(settings_.summary_file);
    out << summary.dump(2) << '\n';
    if (!out)
        std::fprintf(stderr, "dorado_ros: error: cannot write %s\n",
                     settings_.summary_file.c_str());
}

}  // namespace dorado::ros_node
