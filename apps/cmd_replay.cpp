// `dorado replay RECORDING`: a rosbag2 recording published on DDS with ROS 2's conventions, as
// `ros2 bag play` would, so that dorado_ros2 (or any ROS 2 node) runs on it without ROS 2
// installed. Built with Cyclone DDS (cmd_replay_none.cpp without).
#include <cstdio>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "commands.hpp"
#include "dorado/io/recorded_messages.hpp"
#include "dorado/ros2/replay.hpp"

namespace dorado::apps {
namespace {

int Run(const std::string &path, const ros2::ReplayOptions &options) {
    options.Validate();
    const auto messages = io::OpenRecordedMessages(path, options.topics);
    ros2::Participant participant(ros2::DomainFromEnvironment());
    std::fprintf(stderr, "replay: %s on domain %u at %.3gx\n", path.c_str(), participant.domain(),
                 options.rate);
    const ros2::ReplayReport report = ros2::Replay(
        *messages, participant, options,
        [](long long count) { std::fprintf(stderr, "replay: %lld messages published\r", count); });
    for (const std::string &skipped : report.skipped_topics)
        std::fprintf(stderr, "replay: not published: %s\n", skipped.c_str());
    long long total = 0;
    for (const auto &[topic, count] : report.published) {
        std::printf("replay: %s: %lld messages\n", topic.c_str(), count);
        total += count;
    }
    std::printf("replay: %lld messages in %.2f s; latest against the schedule %.1f ms\n", total,
                report.duration_s, report.max_behind_ms);
    for (const std::string &problem : report.problems)
        std::fprintf(stderr, "replay: skipped: %s\n", problem.c_str());
    if (!report.acknowledged)
        std::fprintf(stderr, "replay: a reliable subscriber did not acknowledge every message\n");
    if (total == 0) {
        std::fprintf(stderr, "replay: error: %s: nothing to publish\n", path.c_str());
        return 1;
    }
    return report.problems.empty() ? 0 : 2;
}

}  // namespace

void RegisterReplayCommand(CLI::App &app) {
    auto *cmd = app.add_subcommand(
        "replay",
        "Publish a rosbag2 recording's PointCloud2 and Imu topics on DDS with ROS 2's names, "
        "types, "
        "QoS and CDR (domain ROS_DOMAIN_ID), at the recorded rate or --rate times it, as `ros2 bag "
        "play` would. Exit 2 when messages had to be skipped");
    auto path = std::make_shared<std::string>();
    auto options = std::make_shared<ros2::ReplayOptions>();
    auto topics = std::make_shared<std::vector<std::string>>();
    auto remaps = std::make_shared<std::vector<std::string>>();
    cmd->add_option("recording", *path, "rosbag2 folder (metadata.yaml), .db3 or .mcap")
        ->required();
    cmd->add_option("--rate,-r", options->rate, "times the recorded rate (> 0)")
        ->capture_default_str();
    cmd->add_option("--topics", *topics, "only these topics (default: every one it can publish)");
    cmd->add_option("--remap", *remaps, "publish topic FROM under the name TO (FROM:=TO)")
        ->type_name("FROM:=TO");
    cmd->add_option("--start-offset", options->start_offset_s, "skip this much of the start [s]");
    cmd->add_option("--playback-duration", options->playback_duration_s,
                    "play only this much of the recording [s] (0: all)");
    cmd->add_option("--wait-subscribers", options->wait_subscribers_s,
                    "wait up to this long [s] until every topic has a subscriber before playing");
    cmd->add_flag("--clock", options->clock,
                  "publish /clock (rosgraph_msgs/msg/Clock) at each message's recorded time, for "
                  "nodes with use_sim_time");
    cmd->callback([path, options, topics, remaps]() {
        options->topics = std::set<std::string>(topics->begin(), topics->end());
        for (const std::string &rule : *remaps) {
            const std::size_t at = rule.find(":=");
            if (at == std::string::npos || at == 0 || at + 2 == rule.size())
                throw CLI::ValidationError("--remap", rule + ": expected FROM:=TO");
            options->remaps[rule.substr(0, at)] = rule.substr(at + 2);
        }
        const int code = Run(*path, *options);
        if (code != 0) throw CLI::RuntimeError(code);
    });
}

}  // namespace dorado::apps
