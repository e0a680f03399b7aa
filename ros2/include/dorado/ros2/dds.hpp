#pragma once
/// @file dds.hpp
/// ROS 2's conventions on Cyclone DDS, without rclcpp: the domain from ROS_DOMAIN_ID, topic names
/// (`/a/b` -> `rt/a/b`), the QoS profiles of rclcpp (rmw/qos_profiles.h), and RAII entities: a
/// participant, a typed writer of an idlc-generated message, and a reader that hands over each
/// message's CDR bytes (for dorado_io's codec, the rosbag2 reader's).

#include <dds/dds.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace dorado::ros2 {

/// A DDS call that failed (its return code in words).
class DdsError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// ROS 2's domain: ROS_DOMAIN_ID (unset or empty: 0). Throws std::invalid_argument naming the
/// variable when it is not an integer in 0..232.
[[nodiscard]] uint32_t DomainFromEnvironment();

/// The DDS topic of a ROS 2 topic name: "rt" + the fully qualified name ("/a/b" -> "rt/a/b"; a
/// relative "a/b" is taken in the root namespace). Throws std::invalid_argument for an empty or
/// malformed name (empty tokens, characters outside [A-Za-z0-9_/~{}]).
[[nodiscard]] std::string DdsTopicName(const std::string &ros_name);

/// The QoS profiles ROS 2 names (rmw's qos_profiles.h; /tf as tf2_ros broadcasts it).
enum class QosProfile {
    kSensorData,      ///< best effort, keep last 5, volatile (rmw_qos_profile_sensor_data)
    kDefault,         ///< reliable, keep last 10, volatile (rmw_qos_profile_default)
    kTf,              ///< reliable, keep last 100, volatile (tf2_ros::DynamicBroadcasterQoS)
    kTransientLocal,  ///< reliable, keep last 1, transient local (/tf_static, latched clouds)
    kClock,           ///< best effort, keep last 1, volatile (rclcpp::ClockQoS)
};

/// The profile's QoS, with ROS 2's data representation (XCDR1, plain CDR) and `depth` when > 0.
/// The caller deletes it (dds_delete_qos); QosPtr does.
struct QosDeleter {
    void operator()(dds_qos_t *qos) const { dds_delete_qos(qos); }
};
using QosPtr = std::unique_ptr<dds_qos_t, QosDeleter>;
[[nodiscard]] QosPtr MakeQos(QosProfile profile, int32_t depth = 0);

/// A DDS entity deleted with its children when this goes.
class Entity {
  public:
    Entity() = default;
    explicit Entity(dds_entity_t handle) : handle_(handle) {}
    Entity(Entity &&other) noexcept : handle_(other.handle_) { other.handle_ = 0; }
    Entity &operator=(Entity &&other) noexcept;
    ~Entity();
    [[nodiscard]] dds_entity_t get() const { return handle_; }

  private:
    dds_entity_t handle_ = 0;
};

/// A domain participant on `domain` (DomainFromEnvironment() for a node).
class Participant {
  public:
    explicit Participant(uint32_t domain);
    [[nodiscard]] dds_entity_t get() const { return participant_.get(); }
    [[nodiscard]] uint32_t domain() const { return domain_; }
    /// The topic of an idlc type under a ROS 2 name (created once per name).
    [[nodiscard]] dds_entity_t Topic(const std::string &ros_name,
                                     const dds_topic_descriptor_t &type);

  private:
    Entity participant_;
    uint32_t domain_;
    std::vector<std::pair<std::string, dds_entity_t>> topics_;
};

/// A writer of one idlc-generated type (T is its C struct, `type` its descriptor).
class Writer {
  public:
    Writer(Participant &participant, const std::string &ros_name,
           const dds_topic_descriptor_t &type, QosProfile profile, int32_t depth = 0);
    /// Writes one sample (a T*). Throws DdsError.
    void Write(const void *sample) const;
    /// Readers matched now.
    [[nodiscard]] int Subscribers() const;
    /// Waits until every reliable reader acknowledged what was written (false on timeout).
    bool WaitForAcks(std::chrono::milliseconds timeout) const;
    [[nodiscard]] const std::string &ros_name() const { return ros_name_; }

  private:
    std::string ros_name_;
    Entity writer_;
};

/// A reader that hands over each message's serialized bytes (CDR with the 4-byte encapsulation,
/// as rosbag2 stores them) and the number of matched publishers when it changes. The callbacks
/// run on Cyclone's receive thread: keep them short.
class RawReader {
  public:
    using OnMessage = std::function<void(std::vector<uint8_t> bytes)>;
    using OnPublishers = std::function<void(int count)>;
    RawReader(Participant &participant, const std::string &ros_name,
              const dds_topic_descriptor_t &type, QosProfile profile, int32_t depth,
              OnMessage on_message, OnPublishers on_publishers = {});
    ~RawReader();
    RawReader(const RawReader &) = delete;
    RawReader &operator=(const RawReader &) = delete;
    /// Publishers matched now.
    [[nodiscard]] int Publishers() const;
    [[nodiscard]] dds_entity_t get() const { return reader_.get(); }

  private:
    static void DataAvailable(dds_entity_t reader, void *self);
    static void SubscriptionMatched(dds_entity_t reader, dds_subscription_matched_status_t status,
                                    void *self);
    OnMessage on_message_;
    OnPublishers on_publishers_;
    Entity reader_;
};

/// Takes every sample waiting on `reader` as CDR bytes (what RawReader does on data available).
[[nodiscard]] std::vector<std::vector<uint8_t>> TakeSerialized(dds_entity_t reader);

}  // namespace dorado::ros2
