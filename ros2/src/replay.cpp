#include "dorado/ros2/replay.hpp"

#include <algorithm>
#include <chrono>
#include <memory>
#include <stdexcept>
#include <thread>

#include "dorado/io/cdr_messages.hpp"
#include "dorado/ros2/ros2_convert.hpp"

namespace dorado::ros2 {
namespace {

using Steady = std::chrono::steady_clock;
constexpr const char *kCloud2 = "sensor_msgs/msg/PointCloud2";
constexpr const char *kImu = "sensor_msgs/msg/Imu";

// A recorded message decoded with dorado_io's codec and written as the generated type (Cyclone
// serializes it again: the same bytes, test_ros2_messages checks).
void Publish(const Writer &writer, const std::string &type, const std::vector<uint8_t> &bytes) {
    if (type == kCloud2) {
        const io::CdrPointCloud2 cloud = io::DecodePointCloud2Cdr(bytes);
        std::vector<sensor_msgs_msg_dds__PointField_> fields;
        const sensor_msgs_msg_dds__PointCloud2_ msg = CloudOf(cloud, fields);
        writer.Write(&msg);
    } else {
        const io::CdrImu imu = io::DecodeImuCdr(bytes);  // the message borrows its frame_id
        const sensor_msgs_msg_dds__Imu_ msg = ImuOf(imu);
        writer.Write(&msg);
    }
}

void WaitForSubscribers(const std::map<std::string, std::unique_ptr<Writer>> &writers,
                        double timeout_s) {
    const Steady::time_point end = Steady::now() + std::chrono::duration_cast<Steady::duration>(
                                                       std::chrono::duration<double>(timeout_s));
    auto all_matched = [&] {
        for (const auto &[topic, writer] : writers)
            if (writer->Subscribers() == 0) return false;
        return true;
    };
    while (Steady::now() < end && !all_matched())
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    // Matched writers see the readers; give the readers the same moment to see the writers.
    if (all_matched()) std::this_thread::sleep_for(std::chrono::milliseconds(200));
}

}  // namespace

void ReplayOptions::Validate() const {
    if (!(rate > 0.0)) throw std::invalid_argument("--rate must be > 0");
    if (!(start_offset_s >= 0.0)) throw std::invalid_argument("--start-offset must be >= 0");
    if (!(playback_duration_s >= 0.0))
        throw std::invalid_argument("--playback-duration must be >= 0");
    if (!(wait_subscribers_s >= 0.0))
        throw std::invalid_argument("--wait-subscribers must be >= 0");
}

bool Replayable(const std::string &type) {
    return type == kCloud2 || type == kImu;
}

ReplayReport Replay(io::RecordedMessages &messages, Participant &participant,
                    const ReplayOptions &options, const std::function<void(long long)> &progress) {
    options.Validate();
    ReplayReport report;
    std::map<std::string, std::string> types;
    std::map<std::string, std::unique_ptr<Writer>> writers;
    for (const io::RecordedTopic &topic : messages.topics()) {
        if (!options.topics.empty() && !options.topics.count(topic.name)) continue;
        if (!Replayable(topic.type)) {
            report.skipped_topics.push_back(topic.name + " [" + topic.type +
                                            "]: not a type dorado replay publishes (" + kCloud2 +
                                            ", " + kImu + ")");
            continue;
        }
        types[topic.name] = topic.type;
        const auto remap = options.remaps.find(topic.name);
        // ros2 bag play's default: reliable, volatile; a deep history for a slow subscriber.
        writers[topic.name] = std::make_unique<Writer>(
            participant, remap == options.remaps.end() ? topic.name : remap->second,
            topic.type == kCloud2 ? sensor_msgs_msg_dds__PointCloud2__desc
                                  : sensor_msgs_msg_dds__Imu__desc,
            QosProfile::kDefault, 1000);
    }
    for (const std::string &wanted : options.topics)
        if (!types.count(wanted) &&
            std::none_of(report.skipped_topics.begin(), report.skipped_topics.end(),
                         [&](const std::string &s) { return s.rfind(wanted + " [", 0) == 0; }))
            report.skipped_topics.push_back(wanted + ": not in the recording");
    std::unique_ptr<Writer> clock;
    if (options.clock)
        clock = std::make_unique<Writer>(participant, "/clock", rosgraph_msgs_msg_dds__Clock__desc,
                                         QosProfile::kClock);
    if (options.wait_subscribers_s > 0.0) WaitForSubscribers(writers, options.wait_subscribers_s);

    int64_t first_ns = -1;
    Steady::time_point start, last_progress = Steady::now();
    long long count = 0;
    io::RecordedMessage m;
    while (messages.Next(m)) {
        if (!m.problem.empty()) {
            report.problems.push_back(m.problem);
            continue;
        }
        const auto type = types.find(m.topic);
        if (type == types.end()) continue;
        if (first_ns < 0)
            first_ns = m.log_time_ns + static_cast<int64_t>(options.start_offset_s * 1e9);
        if (m.log_time_ns < first_ns) continue;
        const double since_s = static_cast<double>(m.log_time_ns - first_ns) * 1e-9;
        if (options.playback_duration_s > 0.0 && since_s > options.playback_duration_s) break;
        if (count == 0) start = Steady::now();
        const Steady::time_point due =
            start + std::chrono::duration_cast<Steady::duration>(
                        std::chrono::duration<double>(since_s / options.rate));
        std::this_thread::sleep_until(due);
        report.max_behind_ms =
            std::max(report.max_behind_ms,
                     std::chrono::duration<double, std::milli>(Steady::now() - due).count());
        if (clock) {
            const rosgraph_msgs_msg_dds__Clock_ now{TimeOf(m.log_time_ns)};
            clock->Write(&now);
        }
        try {
            Publish(*writers.at(m.topic), type->second, m.data);
        } catch (const io::DecodeError &e) {
            report.problems.push_back(m.topic + " at log time " + std::to_string(m.log_time_ns) +
                                      " ns: " + e.what());
            continue;
        }
        ++report.published[m.topic];
        ++count;
        if (progress && Steady::now() - last_progress > std::chrono::seconds(1)) {
            last_progress = Steady::now();
            progress(count);
        }
    }
    if (count > 0) report.duration_s = std::chrono::duration<double>(Steady::now() - start).count();
    for (const auto &[topic, writer] : writers)
        report.acknowledged &= writer->WaitForAcks(std::chrono::seconds(10));
    // Best-effort subscribers (a node's sensor-data QoS) acknowledge nothing: without a moment
    // before the writers go, the last message can be lost with them.
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    return report;
}

}  // namespace dorado::ros2
