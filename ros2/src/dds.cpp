#include "dorado/ros2/dds.hpp"

#include <dds/ddsi/ddsi_serdata.h>

#include <cctype>
#include <cstdlib>

namespace dorado::ros2 {
namespace {

dds_entity_t Check(dds_entity_t handle, const std::string &what) {
    if (handle < 0) throw DdsError(what + ": " + dds_strretcode(handle) + " (Cyclone DDS)");
    return handle;
}

}  // namespace

uint32_t DomainFromEnvironment() {
    const char *text = std::getenv("ROS_DOMAIN_ID");
    if (!text || !*text) return 0;
    char *end = nullptr;
    const long domain = std::strtol(text, &end, 10);
    // rmw: 0..232 (the UDP ports of higher domains overflow the port range).
    if (*end != '\0' || domain < 0 || domain > 232)
        throw std::invalid_argument("ROS_DOMAIN_ID='" + std::string(text) +
                                    "' is not a domain id (an integer 0..232)");
    return static_cast<uint32_t>(domain);
}

std::string DdsTopicName(const std::string &ros_name) {
    const std::string name = !ros_name.empty() && ros_name[0] == '/' ? ros_name : "/" + ros_name;
    bool ok = name.size() > 1 && name.back() != '/' && name.find("//") == std::string::npos;
    for (const char c : name)
        ok &= std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '/';
    if (!ok)
        throw std::invalid_argument("'" + ros_name +
                                    "' is not a ROS 2 topic name (tokens of [A-Za-z0-9_] "
                                    "separated by '/', not empty)");
    return "rt" + name;
}

QosPtr MakeQos(QosProfile profile, int32_t depth) {
    QosPtr qos(dds_create_qos());
    bool reliable = true, transient_local = false;
    int32_t keep = 10;
    switch (profile) {
        case QosProfile::kSensorData:
            reliable = false, keep = 5;
            break;
        case QosProfile::kDefault:
            break;
        case QosProfile::kTf:
            keep = 100;
            break;
        case QosProfile::kTransientLocal:
            transient_local = true, keep = 1;
            break;
        case QosProfile::kClock:
            reliable = false, keep = 1;
            break;
    }
    dds_qset_reliability(
        qos.get(), reliable ? DDS_RELIABILITY_RELIABLE : DDS_RELIABILITY_BEST_EFFORT, DDS_SECS(1));
    dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, depth > 0 ? depth : keep);
    dds_qset_durability(qos.get(),
                        transient_local ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
    // ROS 2 messages are plain CDR (XCDR1), as rosbag2 stores them.
    const dds_data_representation_id_t xcdr1 = DDS_DATA_REPRESENTATION_XCDR1;
    dds_qset_data_representation(qos.get(), 1, &xcdr1);
    return qos;
}

Entity &Entity::operator=(Entity &&other) noexcept {
    if (this != &other) {
        if (handle_ > 0) dds_delete(handle_);
        handle_ = other.handle_;
        other.handle_ = 0;
    }
    return *this;
}

Entity::~Entity() {
    if (handle_ > 0) dds_delete(handle_);
}

Participant::Participant(uint32_t domain)
    : participant_(Check(dds_create_participant(domain, nullptr, nullptr),
                         "cannot create a DDS participant on domain " + std::to_string(domain))),
      domain_(domain) {}

dds_entity_t Participant::Topic(const std::string &ros_name, const dds_topic_descriptor_t &type) {
    for (const auto &[name, topic] : topics_)
        if (name == ros_name) return topic;
    const std::string dds_name = DdsTopicName(ros_name);
    const dds_entity_t topic =
        Check(dds_create_topic(get(), &type, dds_name.c_str(), nullptr, nullptr),
              "cannot create topic " + dds_name + " [" + type.m_typename + "]");
    topics_.emplace_back(ros_name, topic);
    return topic;
}

Writer::Writer(Participant &participant, const std::string &ros_name,
               const dds_topic_descriptor_t &type, QosProfile profile, int32_t depth)
    : ros_name_(ros_name) {
    const QosPtr qos = MakeQos(profile, depth);
    writer_ = Entity(Check(
        dds_create_writer(participant.get(), participant.Topic(ros_name, type), qos.get(), nullptr),
        "cannot create a writer of " + ros_name));
}

void Writer::Write(const void *sample) const {
    const dds_return_t rc = dds_write(writer_.get(), sample);
    if (rc < 0) throw DdsError("writing " + ros_name_ + ": " + dds_strretcode(rc));
}

int Writer::Subscribers() const {
    dds_publication_matched_status_t status;
    if (dds_get_publication_matched_status(writer_.get(), &status) < 0) return 0;
    return static_cast<int>(status.current_count);
}

bool Writer::WaitForAcks(std::chrono::milliseconds timeout) const {
    return dds_wait_for_acks(writer_.get(), DDS_MSECS(timeout.count())) == DDS_RETCODE_OK;
}

RawReader::RawReader(Participant &participant, const std::string &ros_name,
                     const dds_topic_descriptor_t &type, QosProfile profile, int32_t depth,
                     OnMessage on_message, OnPublishers on_publishers)
    : on_message_(std::move(on_message)), on_publishers_(std::move(on_publishers)) {
    const QosPtr qos = MakeQos(profile, depth);
    dds_listener_t *listener = dds_create_listener(this);
    dds_lset_data_available(listener, &RawReader::DataAvailable);
    dds_lset_subscription_matched(listener, &RawReader::SubscriptionMatched);
    const dds_entity_t reader = dds_create_reader(
        participant.get(), participant.Topic(ros_name, type), qos.get(), listener);
    dds_delete_listener(listener);
    reader_ = Entity(Check(reader, "cannot create a reader of " + ros_name));
}

RawReader::~RawReader() {
    reader_ = Entity();  // waits for a callback in progress, before the callbacks go
}

int RawReader::Publishers() const {
    dds_subscription_matched_status_t status;
    if (dds_get_subscription_matched_status(reader_.get(), &status) < 0) return 0;
    return static_cast<int>(status.current_count);
}

void RawReader::DataAvailable(dds_entity_t reader, void *self) {
    for (auto &bytes : TakeSerialized(reader))
        static_cast<RawReader *>(self)->on_message_(std::move(bytes));
}

void RawReader::SubscriptionMatched(dds_entity_t, dds_subscription_matched_status_t status,
                                    void *self) {
    auto *me = static_cast<RawReader *>(self);
    if (me->on_publishers_ && status.current_count_change != 0)
        me->on_publishers_(static_cast<int>(status.current_count));
}

std::vector<std::vector<uint8_t>> TakeSerialized(dds_entity_t reader) {
    std::vector<std::vector<uint8_t>> out;
    while (true) {
        struct ddsi_serdata *serdata = nullptr;
        dds_sample_info_t info;
        if (dds_takecdr(reader, &serdata, 1, &info, DDS_ANY_STATE) <= 0) break;
        if (info.valid_data) {
            std::vector<uint8_t> bytes(ddsi_serdata_size(serdata));
            ddsi_serdata_to_ser(serdata, 0, bytes.size(), bytes.data());
            out.push_back(std::move(bytes));
        }
        ddsi_serdata_unref(serdata);
    }
    return out;
}

}  // namespace dorado::ros2
