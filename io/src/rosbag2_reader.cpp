// rosbag2 recordings (a folder with metadata.yaml, or one .db3 or .mcap): the storage files are
// merged into one log-time-ordered stream holding one message per file, and each message is
// decoded from CDR with the same field map, Doppler sign, topic keys and stamp rule as ROS1 bags.
#include <map>
#include <utility>

#include "dorado/io/cdr_messages.hpp"
#include "readers.hpp"
#include "rosbag2_storage.hpp"

namespace dorado::io {

namespace {

constexpr const char *kCloud2 = "sensor_msgs/msg/PointCloud2";

/// The header stamp when the driver set one, else the time the message was recorded (as ROS1).
int64_t StampOf(const CdrHeader &header, int64_t log_time_ns) {
    return header.stamp_ns == 0 ? log_time_ns : header.stamp_ns;
}

StampedPose PoseOf(const CdrPose &pose, int64_t stamp_ns) {
    StampedPose out;
    out.stamp_ns = stamp_ns;
    out.T_world_body.linear() = pose.orientation.normalized().toRotationMatrix();
    out.T_world_body.translation() = pose.position;
    return out;
}

class Rosbag2Reader final : public DatasetReader {
  public:
    explicit Rosbag2Reader(const DatasetConfig &config) : config_(config) {
        const RosbagSource &bag = config.rosbag;
        if (!bag.radar_trigger_topic.empty())
            throw DatasetError(bag.path +
                               ": rosbag.radar_trigger_topic is read from ROS1 bags only; stamp "
                               "the scans in the recording or leave the key empty");
        std::vector<std::pair<std::string, std::string>> topics{
            {bag.radar_topic, "rosbag.radar_topic"}};
        if (!bag.imu_topic.empty()) topics.emplace_back(bag.imu_topic, "rosbag.imu_topic");
        if (!bag.ground_truth_topic.empty())
            topics.emplace_back(bag.ground_truth_topic, "rosbag.ground_truth_topic");
        std::set<std::string> selected;
        for (const auto &topic : topics) selected.insert(topic.first);
        messages_ = OpenRecordedMessages(bag.path, selected);
        CheckTopics(topics);
    }

    bool Next(DatasetEvent &event) override {
        Rosbag2Message message;
        if (!messages_->Next(message)) return false;
        Convert(message, event);
        return true;
    }

    [[nodiscard]] std::string source() const override { return config_.rosbag.path; }

  private:
    void CheckTopics(const std::vector<std::pair<std::string, std::string>> &topics) {
        std::map<std::string, std::string> present;
        for (const auto &t : messages_->topics()) present.emplace(t.name, t.type);
        for (const auto &[topic, key] : topics) {
            if (present.count(topic)) continue;
            std::string list;
            for (const auto &[t, type] : present) list += "\n  " + t + " [" + type + "]";
            throw DatasetError(config_.rosbag.path + ": topic '" + topic + "' is not in the bag (" +
                               key + "); topics:" + (list.empty() ? std::string(" (none)") : list));
        }
        const RosbagSource &bag = config_.rosbag;
        ExpectType(present, bag.radar_topic, {kCloud2});
        ExpectType(present, bag.imu_topic, {"sensor_msgs/msg/Imu"});
        ExpectType(present, bag.ground_truth_topic,
                   {"nav_msgs/msg/Odometry", "geometry_msgs/msg/PoseStamped"});
        if (!bag.ground_truth_topic.empty())
            gt_is_odometry_ = present.at(bag.ground_truth_topic) == "nav_msgs/msg/Odometry";
    }

    void ExpectType(const std::map<std::string, std::string> &present, const std::string &topic,
                    const std::vector<std::string> &accepted) const {
        if (topic.empty()) return;
        const std::string &type = present.at(topic);
        std::string list;
        for (const auto &a : accepted) {
            if (a == type) return;
            list += (list.empty() ? "" : " or ") + a;
        }
        throw DatasetError(config_.rosbag.path + ": topic " + topic + " has type " + type +
                           ", expected " + list);
    }

    void Convert(const Rosbag2Message &m, DatasetEvent &event) {
        event = DatasetEvent{};
        if (!m.problem.empty()) {
            event.kind = DatasetEvent::Kind::kBadScan;
            event.scan_index = radar_count_;
            event.problem = m.problem + " [" + std::to_string(radar_count_) + " scans on " +
                            config_.rosbag.radar_topic + " read before it]";
            return;
        }
        const RosbagSource &bag = config_.rosbag;
        try {
            if (m.topic == bag.radar_topic) return ConvertRadar(m, event);
            if (m.topic == bag.imu_topic) {
                const CdrImu imu = DecodeImuCdr(m.data);
                event.kind = DatasetEvent::Kind::kImu;
                event.stamp_ns = StampOf(imu.header, m.log_time_ns);
                event.imu.stamp_ns = event.stamp_ns;
                event.imu.omega_imu_radps = imu.omega_radps;
                event.imu.accel_imu_mps2 = imu.accel_mps2;
                return;
            }
            const CdrPose pose =
                gt_is_odometry_ ? DecodeOdometryCdr(m.data) : DecodePoseStampedCdr(m.data);
            event.kind = DatasetEvent::Kind::kGroundTruth;
            event.stamp_ns = StampOf(pose.header, m.log_time_ns);
            event.ground_truth = PoseOf(pose, event.stamp_ns);
        } catch (const DecodeError &e) {
            event = DatasetEvent{};
            event.kind = DatasetEvent::Kind::kBadScan;
            event.scan_index = radar_count_;
            event.problem = bag.path + ": topic " + m.topic + " at log time " +
                            std::to_string(m.log_time_ns) + " ns unreadable: " + e.what();
        }
    }

    void ConvertRadar(const Rosbag2Message &m, DatasetEvent &event) {
        event.scan_index = radar_count_++;
        event.stamp_ns = m.log_time_ns;
        try {
            const CdrPointCloud2 msg = DecodePointCloud2Cdr(m.data);
            event.stamp_ns = StampOf(msg.header, m.log_time_ns);
            event.scan = DecodePointCloud(msg.cloud, config_.fields);
            event.scan.frame_id = msg.header.frame_id;
        } catch (const DecodeError &e) {
            event.kind = DatasetEvent::Kind::kBadScan;
            event.problem = config_.rosbag.path + ": topic " + config_.rosbag.radar_topic +
                            ", scan " + std::to_string(event.scan_index) + ": " + e.what();
            return;
        }
        event.kind = DatasetEvent::Kind::kRadarScan;
        event.scan.stamp_ns = event.stamp_ns;
        event.removed_nonfinite_points = RemoveNonFinitePoints(event.scan);
    }

    DatasetConfig config_;
    std::unique_ptr<RecordedMessages> messages_;
    bool gt_is_odometry_ = false;
    std::size_t radar_count_ = 0;
};

}  // namespace

std::vector<TopicSummary> ListRosbag2Topics(const DatasetConfig &config) {
    std::map<std::string, TopicSummary> topics;
    for (const auto &storage : OpenRosbag2Storages(config.rosbag.path, {})) {
        for (const auto &t : storage->topics()) {
            topics[t.name].topic = t.name;
            topics[t.name].type = t.type;
        }
        Rosbag2Message m;
        while (storage->Next(m)) {
            if (!m.problem.empty()) continue;  // the reader reports it
            TopicSummary &summary = topics[m.topic];
            if (summary.messages++ == 0 || m.log_time_ns < summary.first_ns)
                summary.first_ns = m.log_time_ns;
            summary.last_ns = std::max(summary.last_ns, m.log_time_ns);
            if (summary.type != kCloud2 || !summary.fields.empty()) continue;
            try {
                summary.fields = DescribeFields(DecodePointCloud2Cdr(m.data).cloud.fields);
            } catch (const DecodeError &e) {
                summary.fields = std::string("(first message unreadable: ") + e.what() + ")";
            }
        }
    }
    std::vector<TopicSummary> out;
    for (auto &[name, summary] : topics) out.push_back(summary);
    return out;
}

std::unique_ptr<DatasetReader> OpenRosbag2Reader(const DatasetConfig &config) {
    return std::make_unique<Rosbag2Reader>(config);
}

}  // namespace dorado::io
