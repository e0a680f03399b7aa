#include "ros2_node.hpp"

#include <chrono>
#include <cstdio>

#include "dorado/io/cdr_messages.hpp"
#include "dorado/ros2/ros2_convert.hpp"

namespace dorado::ros2 {
namespace {

using ros_node::CloudTopic;
using ros_node::OdometryTopic;

std::unique_ptr<Writer> MakeWriter(Participant &participant, const RosArgs &args, const char *topic,
                                   const dds_topic_descriptor_t &type, QosProfile profile) {
    return std::make_unique<Writer>(participant, Remapped(args, topic), type, profile);
}

}  // namespace

Ros2Node::Ros2Node(const RosArgs &args, ros_node::NodeSettings settings, bool use_sim_time)
    : name_(args.node_name), use_sim_time_(use_sim_time), participant_(DomainFromEnvironment()) {
    const dds_topic_descriptor_t &odometry = nav_msgs_msg_dds__Odometry__desc;
    const dds_topic_descriptor_t &cloud = sensor_msgs_msg_dds__PointCloud2__desc;
    odom_ = MakeWriter(participant_, args, "/doppler_odom", odometry, QosProfile::kDefault);
    tf_ = MakeWriter(participant_, args, "/tf", tf2_msgs_msg_dds__TFMessage__desc, QosProfile::kTf);
    tf_static_ = MakeWriter(participant_, args, "/tf_static", tf2_msgs_msg_dds__TFMessage__desc,
                            QosProfile::kTransientLocal);
    if (settings.front_end.run_mapper) {
        map_odom_ =
            MakeWriter(participant_, args, "/dorado/map_odom", odometry, QosProfile::kDefault);
        smoothed_odom_ =
            MakeWriter(participant_, args, "/dorado/smoothed_odom", odometry, QosProfile::kDefault);
        static_points_ =
            MakeWriter(participant_, args, "/dorado/static_points", cloud, QosProfile::kSensorData);
        dynamic_points_ = MakeWriter(participant_, args, "/dorado/dynamic_points", cloud,
                                     QosProfile::kSensorData);
        local_map_ =
            MakeWriter(participant_, args, "/dorado/local_map", cloud, QosProfile::kTransientLocal);
    }
    cloud_topic_ = Remapped(args, settings.input_topic);
    imu_topic_ = Remapped(args, settings.imu_topic);
    settings.input_topic = cloud_topic_;
    settings.imu_topic = imu_topic_;
    pipeline_ = std::make_unique<ros_node::LivePipeline>(std::move(settings), *this, name_);
    const ros_node::NodeSettings &s = pipeline_->settings();
    if (use_sim_time_)
        clock_reader_ = std::make_unique<RawReader>(
            participant_, Remapped(args, "/clock"), rosgraph_msgs_msg_dds__Clock__desc,
            QosProfile::kClock, 1, [this](std::vector<uint8_t> bytes) {
                try {
                    clock_ns_ = io::DecodeClockCdr(bytes);
                } catch (const io::DecodeError &e) {
                    Log(ros_node::LogLevel::kError, name_ + ": /clock: " + e.what());
                }
            });
    if (s.needs_imu)
        imu_reader_ = std::make_unique<RawReader>(
            participant_, imu_topic_, sensor_msgs_msg_dds__Imu__desc, QosProfile::kSensorData, 1000,
            [this](std::vector<uint8_t> bytes) { OnImu(bytes); },
            [this](int count) { OnPublishers(imu_topic_, count, imu_lost_); });
    // Best effort (the sensor data profile) matches reliable and best-effort publishers alike; a
    // deep history, as the node, not DDS, decides what is dropped.
    cloud_reader_ = std::make_unique<RawReader>(
        participant_, cloud_topic_, cloud, QosProfile::kSensorData, 100,
        [this](std::vector<uint8_t> bytes) { OnCloud(std::move(bytes)); },
        [this](int count) { OnPublishers(cloud_topic_, count, cloud_lost_); });
    Log(ros_node::LogLevel::kInfo,
        name_ + ": " + s.description + "; domain " + std::to_string(participant_.domain()) +
            "; radar " + cloud_topic_ + " -> " + Remapped(args, "/doppler_odom") + " and /tf " +
            s.tf_from_frame + " -> " + s.tf_to_frame + pipeline_->MapperDescription() +
            (s.needs_imu ? "; IMU " + imu_topic_ : "") + (use_sim_time_ ? "; use_sim_time" : ""));
}

Ros2Node::~Ros2Node() {
    Shutdown();
}

void Ros2Node::OnCloud(std::vector<uint8_t> bytes) {
    const auto arrival = Clock::now();
    auto owner = std::make_shared<const std::vector<uint8_t>>(std::move(bytes));
    io::CdrPointCloud2 msg;
    try {
        msg = io::DecodePointCloud2Cdr(*owner);
    } catch (const io::DecodeError &e) {
        pipeline_->OnUnreadable(e.what());
        return;
    }
    if (!msg.header.frame_id.empty())
        std::call_once(mount_published_, [&] { PublishMount(msg.header.frame_id); });
    ros_node::LiveCloud cloud;
    cloud.arrival = arrival;
    cloud.stamp_ns = msg.header.stamp_ns;
    cloud.frame_id = msg.header.frame_id;
    cloud.view = msg.cloud;
    cloud.owner = owner;
    pipeline_->OnCloud(std::move(cloud));
}

void Ros2Node::OnImu(const std::vector<uint8_t> &bytes) {
    try {
        const io::CdrImu imu = io::DecodeImuCdr(bytes);
        ImuSample sample;
        sample.stamp_ns = imu.header.stamp_ns;
        sample.omega_imu_radps = imu.omega_radps;
        sample.accel_imu_mps2 = imu.accel_mps2;
        pipeline_->OnImu(sample);
    } catch (const io::DecodeError &e) {
        Log(ros_node::LogLevel::kError, name_ + ": " + imu_topic_ + ": " + e.what());
    }
}

void Ros2Node::OnPublishers(const std::string &topic, int count, bool &lost) {
    if (count == 0) lost = true;
    if (count == 0 || lost) pipeline_->OnPublishers(topic, count);
    if (count > 0) lost = false;
}

// The mount on /tf_static: tf_to_frame -> the radar's frame (T_child_radar = T_base_child^-1
// T_base_radar), once the radar's frame name is known.
void Ros2Node::PublishMount(const std::string &radar_frame) {
    const ros_node::NodeSettings &s = pipeline_->settings();
    const ros_node::TransformOutput mount{
        0, s.tf_to_frame, radar_frame,
        s.T_base_child.inverse() * s.dataset.extrinsics.T_base_radar};
    geometry_msgs_msg_dds__TransformStamped_ transform = TransformOf(mount);
    const tf2_msgs_msg_dds__TFMessage_ msg{{1, 1, &transform, false}};
    tf_static_->Write(&msg);
}

void Ros2Node::Shutdown() {
    if (!pipeline_) return;
    cloud_reader_.reset();
    imu_reader_.reset();
    pipeline_->Shutdown(true);
    for (const Writer *writer : {odom_.get(), map_odom_.get(), smoothed_odom_.get()})
        if (writer && !writer->WaitForAcks(std::chrono::seconds(5)))
            std::fprintf(stderr, "%s: %s: not every subscriber acknowledged the last messages\n",
                         name_.c_str(), writer->ros_name().c_str());
    clock_reader_.reset();
    pipeline_.reset();
}

const Writer &Ros2Node::WriterOf(OdometryTopic topic) const {
    switch (topic) {
        case OdometryTopic::kMapOdom:
            return *map_odom_;
        case OdometryTopic::kSmoothedOdom:
            return *smoothed_odom_;
        case OdometryTopic::kDopplerOdom:
            break;
    }
    return *odom_;
}

const Writer &Ros2Node::WriterOf(CloudTopic topic) const {
    switch (topic) {
        case CloudTopic::kStaticPoints:
            return *static_points_;
        case CloudTopic::kDynamicPoints:
            return *dynamic_points_;
        case CloudTopic::kLocalMap:
            break;
    }
    return *local_map_;
}

void Ros2Node::Publish(OdometryTopic topic, const ros_node::OdometryOutput &odometry) {
    const nav_msgs_msg_dds__Odometry_ msg = OdometryOf(odometry);
    WriterOf(topic).Write(&msg);
}

void Ros2Node::Publish(const ros_node::TransformOutput &transform) {
    geometry_msgs_msg_dds__TransformStamped_ stamped = TransformOf(transform);
    const tf2_msgs_msg_dds__TFMessage_ msg{{1, 1, &stamped, false}};
    tf_->Write(&msg);
}

bool Ros2Node::HasSubscribers(CloudTopic topic) const {
    return WriterOf(topic).Subscribers() > 0;
}

void Ros2Node::Publish(CloudTopic topic, const ros_node::CloudOutput &cloud) {
    const ros_node::PackedCloud packed = ros_node::PackCloud(cloud);
    std::vector<sensor_msgs_msg_dds__PointField_> fields;
    const sensor_msgs_msg_dds__PointCloud2_ msg =
        CloudOf(cloud.stamp_ns, cloud.frame_id, packed, fields);
    WriterOf(topic).Write(&msg);
}

// rcutils' console format: [LEVEL] [seconds] text.
void Ros2Node::Log(ros_node::LogLevel level, const std::string &text) {
    static const char *const kLevels[] = {"INFO", "WARN", "ERROR"};
    const double now =
        std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    std::lock_guard<std::mutex> lock(log_mutex_);
    std::fprintf(stderr, "[%s] [%.9f] %s\n", kLevels[static_cast<int>(level)], now, text.c_str());
}

int64_t Ros2Node::NowNs() const {
    if (use_sim_time_) return clock_ns_;
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
}

}  // namespace dorado::ros2
