#pragma once
/// @file live_pipeline.hpp
/// The live nodes' driver of frontend::RadarFrontEnd, without ROS (dorado_ros and dorado_ros2 are
/// thin edges over it). Scans are queued as they arrive and processed in order by one worker
/// thread; what cannot be used (a stamp not after the last one, a scan overtaken while the worker
/// was busy, an undecodable message) is dropped, counted and reported in summarised warnings; an
/// IMU that stalls hands the prior to the Doppler one; a long gap starts over. The outputs go to a
/// LiveSink; the counts and latencies are printed and written (summary_file) at Shutdown.

#include <chrono>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "dorado/core/imu.hpp"
#include "dorado/core/time.hpp"
#include "dorado/frontend/radar_front_end.hpp"
#include "dorado/io/pointcloud_decoder.hpp"
#include "live_input.hpp"
#include "live_sink.hpp"
#include "loop_worker.hpp"
#include "node_settings.hpp"
#include "pose_covariance.hpp"

namespace dorado::ros_node {

/// One radar message as it arrived: its header and a view of its point bytes, which `owner` keeps
/// alive (the ROS message, or the received CDR bytes).
struct LiveCloud {
    int64_t stamp_ns = 0;  ///< 0: the driver left it empty (the node's clock at arrival stands in)
    std::string frame_id;
    io::CloudBufferView view;
    std::shared_ptr<const void> owner;
    Clock::time_point arrival;
};

/// The counts a node reports at exit (and writes to summary_file).
struct LiveCounts {
    long long received = 0, processed = 0, published = 0, resets = 0;
};

class LivePipeline {
  public:
    /// `node_name` prefixes every message ("dorado_ros: ..."). Starts the worker.
    LivePipeline(NodeSettings settings, LiveSink &sink, std::string node_name);
    ~LivePipeline();

    /// A scan arrived (any thread): stamped by the node's clock if unstamped, queued, or the
    /// oldest waiting one dropped as late.
    void OnCloud(LiveCloud cloud);
    /// A radar message that could not even be read (its CDR bytes): counted as received and
    /// dropped.
    void OnUnreadable(const std::string &error);
    /// An IMU sample arrived (any thread); old or repeated stamps are ignored.
    void OnImu(const ImuSample &sample);
    /// The input's publishers went away (count 0) or came back: said once per cause, counted.
    void OnPublishers(const std::string &topic, int count);

    /// Stops the worker (the scans still waiting are dropped and counted). `finish`: the poses
    /// still in the mapper's smoother are written and published (/dorado/smoothed_odom) first.
    /// Then prints the totals (stderr) and writes summary_file. Idempotent.
    void Shutdown(bool finish);

    [[nodiscard]] const NodeSettings &settings() const { return settings_; }
    /// For the node's first line: "; mapper off", "; mapper on, prior P" or "; mapper and loop
    /// closure on, prior P".
    [[nodiscard]] std::string MapperDescription() const;
    [[nodiscard]] LiveCounts counts() const;

  private:
    void Work();
    void Handle(const LiveCloud &cloud);
    bool Decode(const LiveCloud &cloud, RadarScan &scan);
    bool FeedImu(int64_t stamp_ns);
    void WatchImu(bool imu_current, int64_t stamp_ns);
    void PublishWritten(const std::vector<mapping::WrittenPose> &written);
    void Publish(int64_t stamp_ns, const RadarScan &scan, const frontend::FrontEndResult &result);
    void PublishClouds(int64_t stamp_ns, const std::string &radar_frame, const RadarScan &scan,
                       const frontend::FrontEndResult &result);
    void ReportPrior(const frontend::FrontEndResult &result);
    void Drop(const std::string &cause, const std::string &detail);
    bool CountWarning(const std::string &cause, const std::string &detail);  ///< locks
    void Increment(long long &count);                                        ///< locks
    void Log(LogLevel level, const char *format, ...) __attribute__((format(printf, 3, 4)));
    void ReportPeriodically();
    void WriteSummary() const;

    NodeSettings settings_;
    LiveSink &sink_;
    std::string name_;
    frontend::RadarFrontEnd front_end_;
    StampGuard stamps_;
    FaultLog faults_;    ///< dropped scans, by cause
    FaultLog warnings_;  ///< scans used despite a fault (a gap, a prior substitution), lost inputs
    LatencyStats latency_;         ///< arrival -> published
    LatencyStats front_end_time_;  ///< the front end's own time per scan (Process)
    LatencyStats worker_cpu_;      ///< the worker's CPU time per published scan [ms]
    PoseCovariance pose_covariance_;
    Eigen::Isometry3d T_world_base_initial_;

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<LiveCloud> queue_;
    std::deque<ImuSample> imu_;
    int64_t last_imu_stamp_ns_ = 0;
    bool stop_ = false, shut_down_ = false;
    LiveCounts counts_;
    long long late_drops_ = 0, late_drops_seen_ = 0;  ///< a gap the node made is not a stall
    bool imu_stalled_ = false;                        ///< worker only
    Clock::time_point last_report_, last_local_map_;
    /// Loop closure on the written poses, in a thread of its own (mapper and loop_closure.enabled).
    std::unique_ptr<LoopWorker> loops_;
    std::thread worker_;
};

}  // namespace dorado::ros_node
