// ROS1 bags through librosbag-storage, streamed message by message in bag time order.
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>

#include <map>
#include <utility>

#include "dorado/io/ros1_cloud_view.hpp"
#include "readers.hpp"

namespace dorado::io {

namespace {

int64_t ToNanos(const ros::Time &t) {
    return static_cast<int64_t>(t.toNSec());
}

/// The header stamp when the driver set one, else the time the message was recorded.
int64_t StampOf(const std_msgs::Header &header, const rosbag::MessageInstance &m) {
    return header.stamp.isZero() ? ToNanos(m.getTime()) : ToNanos(header.stamp);
}

RadarScan DecodeCloud2(const sensor_msgs::PointCloud2 &msg, const FieldMap &map) {
    return DecodePointCloud(ViewOf(msg), map);
}

/// sensor_msgs/PointCloud (e.g. NTU4DRadLM): xyz in points, everything else in named channels.
RadarScan DecodeCloud1(const sensor_msgs::PointCloud &msg, const FieldMap &map) {
    const std::size_t n = msg.points.size();
    auto channel = [&](const std::string &name, bool required,
                       const char *role) -> const std::vector<float> * {
        if (name.empty()) {
            if (required) throw DecodeError(std::string("the field map gives no name for ") + role);
            return nullptr;
        }
        for (const auto &c : msg.channels) {
            if (c.name != name) continue;
            if (c.values.size() != n) {
                throw DecodeError("channel '" + name + "' has " + std::to_string(c.values.size()) +
                                  " values for " + std::to_string(n) + " points");
            }
            return &c.values;
        }
        std::string present;
        for (const auto &c : msg.channels) present += (present.empty() ? "" : ", ") + c.name;
        throw DecodeError("missing channel '" + name + "' (the field map's " + role +
                          "); channels present: " + (present.empty() ? "(none)" : present));
    };
    const auto *doppler = channel(map.doppler, true, "doppler");
    const auto *power = channel(map.power, false, "power");
    RadarScan scan;
    scan.has_power = power != nullptr;
    scan.Resize(static_cast<Eigen::Index>(n));
    for (std::size_t i = 0; i < n; ++i) {
        const auto k = static_cast<Eigen::Index>(i);
        scan.xyz_radar.col(k) << msg.points[i].x, msg.points[i].y, msg.points[i].z;
        scan.doppler_mps[k] = map.doppler_sign * (*doppler)[i];
        scan.power_db[k] = power ? (*power)[i] : 0.0;
    }
    scan.DeriveSphericalFromXyz();
    return scan;
}

/// Opens for reading; a bag without a readable index (a recording cut off, a copy interrupted) gets
/// a message saying how to rebuild the index.
void OpenBag(rosbag::Bag &bag, const std::string &path) {
    const std::string repair =
        "; if the recording was cut off, `rosbag reindex " + path +
        "` (Debian's python3-rosbag) rebuilds its index from the chunks that survive";
    try {
        bag.open(path, rosbag::bagmode::Read);
    } catch (const rosbag::BagUnindexedException &) {
        throw DatasetError(path + ": the bag has no index" + repair);
    } catch (const rosbag::BagException &e) {
        throw DatasetError(
            path + ": cannot open as a ROS1 bag (truncated or corrupt?): " + e.what() + repair);
    }
}

/// Every topic in the bag with its type, including a topic registered (a connection record) without
/// any message, which `rosbag info` lists with 0 msgs. View::getConnections() omits such a topic;
/// the query of a View is asked about every connection.
std::map<std::string, std::string> TopicTypes(const rosbag::Bag &bag) {
    std::map<std::string, std::string> topics;
    const rosbag::View probe(bag, [&topics](const rosbag::ConnectionInfo *c) {
        topics.emplace(c->topic, c->datatype);
        return false;
    });
    return topics;
}

StampedPose PoseOf(const geometry_msgs::Pose &pose, int64_t stamp_ns) {
    StampedPose out;
    out.stamp_ns = stamp_ns;
    const auto &q = pose.orientation;
    out.T_world_body.linear() =
        Eigen::Quaterniond(q.w, q.x, q.y, q.z).normalized().toRotationMatrix();
    out.T_world_body.translation() << pose.position.x, pose.position.y, pose.position.z;
    return out;
}

class BagReader final : public DatasetReader {
  public:
    explicit BagReader(const DatasetConfig &config) : config_(config) {
        const std::string &path = config.rosbag.path;
        OpenBag(bag_, path);
        // The topics to read, with the dataset description's key that names each.
        std::vector<std::pair<std::string, std::string>> topics{
            {config.rosbag.radar_topic, "rosbag.radar_topic"}};
        if (!config.rosbag.imu_topic.empty())
            topics.emplace_back(config.rosbag.imu_topic, "rosbag.imu_topic");
        if (!config.rosbag.ground_truth_topic.empty())
            topics.emplace_back(config.rosbag.ground_truth_topic, "rosbag.ground_truth_topic");
        if (!config.rosbag.radar_trigger_topic.empty())
            topics.emplace_back(config.rosbag.radar_trigger_topic, "rosbag.radar_trigger_topic");
        try {
            CheckTopicsExist(topics);
            std::vector<std::string> names;
            for (const auto &topic : topics) names.push_back(topic.first);
            view_ = std::make_unique<rosbag::View>(bag_, rosbag::TopicQuery(names));
            it_ = view_->begin();
        } catch (const rosbag::BagException &e) {
            throw DatasetError(path + ": cannot read the bag's index: " + e.what());
        }
    }

    bool Next(DatasetEvent &event) override {
        if (finished_) return false;
        try {
            // Trigger messages are consumed here: they only stamp the scans after them.
            do {
                if (!first_ && it_ != view_->end()) ++it_;
                first_ = false;
                if (it_ == view_->end()) return Finish();
            } while (ConsumedTrigger(*it_));
        } catch (const std::exception &e) {
            // The index itself is unusable from here on: report it and end the stream so that what
            // was read so far is still used.
            event = DatasetEvent{};
            event.kind = DatasetEvent::Kind::kBadScan;
            event.scan_index = radar_count_;
            event.problem = config_.rosbag.path + ": bag index unreadable after " +
                            std::to_string(radar_count_) + " radar messages (" + e.what() +
                            "); stopping the stream here";
            finished_ = true;
            return true;
        }
        const std::size_t message_index = message_count_++;
        try {
            Convert(*it_, event);
        } catch (const DatasetError &) {
            throw;
        } catch (const std::exception &e) {
            // One message whose chunk or bytes are damaged: skip it, keep going.
            const bool radar = event.kind == DatasetEvent::Kind::kRadarScan;
            event = DatasetEvent{};
            event.kind = DatasetEvent::Kind::kBadScan;
            event.scan_index = radar ? radar_count_ - 1 : radar_count_;
            event.problem = config_.rosbag.path + ": message " + std::to_string(message_index) +
                            " on " + it_->getTopic() + " unreadable: " + e.what();
        }
        return true;
    }

    [[nodiscard]] std::string source() const override { return config_.rosbag.path; }

  private:
    bool Finish() {
        finished_ = true;
        return false;
    }

    // A message on rosbag.radar_trigger_topic: remembers its stamp for the next scan.
    bool ConsumedTrigger(const rosbag::MessageInstance &m) {
        if (config_.rosbag.radar_trigger_topic.empty() ||
            m.getTopic() != config_.rosbag.radar_trigger_topic)
            return false;
        try {
            const auto header = m.instantiate<std_msgs::Header>();
            if (header && !header->stamp.isZero()) {
                trigger_ns_ = ToNanos(header->stamp);
                trigger_unused_ = true;
            }
        } catch (const ros::Exception &) {
            // A damaged trigger: the scan after it finds no fresh trigger and says so.
        }
        return true;
    }

    void CheckTopicsExist(const std::vector<std::pair<std::string, std::string>> &topics) {
        const std::map<std::string, std::string> present = TopicTypes(bag_);
        for (const auto &[topic, key] : topics) {
            if (present.count(topic)) continue;
            std::string list;
            for (const auto &[t, type] : present) list += "\n  " + t + " [" + type + "]";
            throw DatasetError(config_.rosbag.path + ": topic '" + topic + "' is not in the bag (" +
                               key + "); topics:" + (list.empty() ? std::string(" (none)") : list));
        }
        ExpectType(present, config_.rosbag.radar_topic,
                   {"sensor_msgs/PointCloud2", "sensor_msgs/PointCloud"});
        ExpectType(present, config_.rosbag.imu_topic, {"sensor_msgs/Imu"});
        ExpectType(present, config_.rosbag.ground_truth_topic,
                   {"nav_msgs/Odometry", "geometry_msgs/PoseStamped"});
        ExpectType(present, config_.rosbag.radar_trigger_topic, {"std_msgs/Header"});
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

    void Convert(const rosbag::MessageInstance &m, DatasetEvent &event) {
        event = DatasetEvent{};
        const std::string &topic = m.getTopic();
        const std::string &type = m.getDataType();
        if (topic == config_.rosbag.radar_topic) {
            event.kind = DatasetEvent::Kind::kRadarScan;
            event.scan_index = radar_count_++;
            ConvertRadar(m, type, event);
        } else if (topic == config_.rosbag.imu_topic) {
            const auto imu = m.instantiate<sensor_msgs::Imu>();
            event.kind = DatasetEvent::Kind::kImu;
            event.stamp_ns = StampOf(imu->header, m);
            event.imu.stamp_ns = event.stamp_ns;
            event.imu.omega_imu_radps << imu->angular_velocity.x, imu->angular_velocity.y,
                imu->angular_velocity.z;
            event.imu.accel_imu_mps2 << imu->linear_acceleration.x, imu->linear_acceleration.y,
                imu->linear_acceleration.z;
        } else {
            event.kind = DatasetEvent::Kind::kGroundTruth;
            if (type == "nav_msgs/Odometry") {
                const auto odom = m.instantiate<nav_msgs::Odometry>();
                event.stamp_ns = StampOf(odom->header, m);
                event.ground_truth = PoseOf(odom->pose.pose, event.stamp_ns);
            } else {
                const auto pose = m.instantiate<geometry_msgs::PoseStamped>();
                event.stamp_ns = StampOf(pose->header, m);
                event.ground_truth = PoseOf(pose->pose, event.stamp_ns);
            }
        }
    }

    void ConvertRadar(const rosbag::MessageInstance &m, const std::string &type,
                      DatasetEvent &event) {
        event.stamp_ns = ToNanos(m.getTime());
        const std::string where = config_.rosbag.path + ": topic " + config_.rosbag.radar_topic +
                                  ", scan " + std::to_string(event.scan_index) + ": ";
        try {
            if (type == "sensor_msgs/PointCloud2") {
                const auto msg = m.instantiate<sensor_msgs::PointCloud2>();
                event.stamp_ns = StampOf(msg->header, m);
                event.scan = DecodeCloud2(*msg, config_.fields);
                event.scan.frame_id = msg->header.frame_id;
            } else {
                const auto msg = m.instantiate<sensor_msgs::PointCloud>();
                event.stamp_ns = StampOf(msg->header, m);
                event.scan = DecodeCloud1(*msg, config_.fields);
                event.scan.frame_id = msg->header.frame_id;
            }
        } catch (const DecodeError &e) {
            event.kind = DatasetEvent::Kind::kBadScan;
            event.problem = where + e.what();
            return;
        } catch (const ros::Exception &e) {
            event.kind = DatasetEvent::Kind::kBadScan;
            event.problem = where + "message does not deserialize: " + e.what();
            return;
        }
        if (!config_.rosbag.radar_trigger_topic.empty()) {
            if (!trigger_unused_) {
                event.kind = DatasetEvent::Kind::kBadScan;
                event.problem = where + "no trigger on " + config_.rosbag.radar_trigger_topic +
                                " (rosbag.radar_trigger_topic) since the previous scan: no stamp";
                return;
            }
            event.stamp_ns =
                trigger_ns_ + static_cast<int64_t>(config_.rosbag.radar_trigger_offset_s * 1e9);
            trigger_unused_ = false;
        }
        event.kind = DatasetEvent::Kind::kRadarScan;
        event.scan.stamp_ns = event.stamp_ns;
        event.removed_nonfinite_points = RemoveNonFinitePoints(event.scan);
    }

    DatasetConfig config_;
    rosbag::Bag bag_;
    std::unique_ptr<rosbag::View> view_;
    rosbag::View::iterator it_;
    bool first_ = true;
    bool finished_ = false;
    std::size_t radar_count_ = 0;
    std::size_t message_count_ = 0;
    int64_t trigger_ns_ = 0;       ///< the newest radar trigger's stamp
    bool trigger_unused_ = false;  ///< no scan took trigger_ns_ yet
};

}  // namespace

std::vector<TopicSummary> ListBagTopics(const DatasetConfig &config) {
    rosbag::Bag bag;
    OpenBag(bag, config.rosbag.path);
    std::map<std::string, TopicSummary> topics;
    for (const auto &[topic, type] : TopicTypes(bag)) {
        auto &summary = topics[topic];
        summary.topic = topic;
        summary.type = type;
    }
    for (auto &[name, summary] : topics) {
        rosbag::View view(bag, rosbag::TopicQuery(name));
        summary.messages = view.size();
        if (summary.messages == 0) continue;
        summary.first_ns = ToNanos(view.getBeginTime());
        summary.last_ns = ToNanos(view.getEndTime());
        if (summary.type != "sensor_msgs/PointCloud2" && summary.type != "sensor_msgs/PointCloud")
            continue;
        try {
            const auto it = view.begin();  // the instance lives inside the iterator
            const rosbag::MessageInstance &first = *it;
            if (const auto cloud2 = first.instantiate<sensor_msgs::PointCloud2>()) {
                std::vector<PointFieldDesc> fields;
                for (const auto &f : cloud2->fields)
                    fields.push_back({f.name, f.offset, f.datatype, f.count});
                summary.fields = DescribeFields(fields);
            } else if (const auto cloud1 = first.instantiate<sensor_msgs::PointCloud>()) {
                summary.fields = "x, y, z";
                for (const auto &c : cloud1->channels) summary.fields += ", " + c.name;
            }
        } catch (const std::exception &e) {
            summary.fields = std::string("(first message unreadable: ") + e.what() + ")";
        }
    }
    std::vector<TopicSummary> out;
    for (auto &[name, summary] : topics) out.push_back(summary);
    return out;
}

std::unique_ptr<DatasetReader> OpenBagReader(const DatasetConfig &config) {
    return std::make_unique<BagReader>(config);
}

}  // namespace dorado::io
