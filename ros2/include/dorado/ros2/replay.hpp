#pragma once
/// @file replay.hpp
/// `dorado replay`: a rosbag2 recording's sensor_msgs/msg/PointCloud2 and sensor_msgs/msg/Imu
/// topics published on DDS with ROS 2's conventions, at the recorded rate (or `rate` times it),
/// as `ros2 bag play` does: every message keeps its recorded header and bytes.

#include <cstdint>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "dorado/io/recorded_messages.hpp"
#include "dorado/ros2/dds.hpp"

namespace dorado::ros2 {

struct ReplayOptions {
    double rate = 1.0;                 ///< times the recorded rate (> 0)
    double start_offset_s = 0.0;       ///< skip this much of the recording's start [s]
    double playback_duration_s = 0.0;  ///< play this much of the recording [s] (0: all)
    double wait_subscribers_s = 0.0;   ///< wait (up to) this long for each topic's subscriber
    bool clock = false;                ///< publish /clock (rosgraph_msgs/msg/Clock) at log time
    std::set<std::string> topics;      ///< the topics to publish (empty: every one dorado can)
    /// Recorded topic name -> the name it is published under (`ros2 bag play --remap`).
    std::map<std::string, std::string> remaps;

    /// Throws std::invalid_argument naming the option.
    void Validate() const;
};

/// What a replay did.
struct ReplayReport {
    std::map<std::string, long long> published;  ///< per topic
    /// Topics not published: "topic [type]: why".
    std::vector<std::string> skipped_topics;
    /// Messages that could not be read (a damaged part of the file, undecodable CDR).
    std::vector<std::string> problems;
    double duration_s = 0.0;     ///< wall time from the first message to the last
    double max_behind_ms = 0.0;  ///< how late the worst message left against its schedule
    bool acknowledged = true;    ///< every reliable subscriber acknowledged everything
};

/// The types replay publishes.
[[nodiscard]] bool Replayable(const std::string &type);

/// Publishes `messages` (opened on every topic) on `participant`. `progress` is called with the
/// messages published so far about once a second. Throws DdsError when a writer cannot be made.
[[nodiscard]] ReplayReport Replay(io::RecordedMessages &messages, Participant &participant,
                                  const ReplayOptions &options,
                                  const std::function<void(long long)> &progress = {});

}  // namespace dorado::ros2
