// ROS 2's conventions on DDS, checked against what ROS 2 itself specifies: the type and topic
// names of the design article "Topic and Service name mapping to DDS" and rmw_cyclonedds, the QoS
// of rmw's qos_profiles.h, ROS_DOMAIN_ID, and the CDR bytes both ways: what dorado_ros2 writes
// (Cyclone serializing the idlc types) decodes with the rosbag2 reader's codec, and messages in
// a rosbag2 recording (written by tests/io/rosbag2_writer.py from the CDR specification) come out
// of Cyclone's serializer with the same bytes after `dorado replay` decodes and republishes them.
#include <gtest/gtest.h>

#include <unistd.h>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <thread>

#include "dorado/io/cdr_messages.hpp"
#include "dorado/io/recorded_messages.hpp"
#include "dorado/ros2/dds.hpp"
#include "dorado/ros2/ros2_convert.hpp"

namespace dorado::ros2 {
namespace {

// Domains of this test's own (the live test uses 61..68).
constexpr uint32_t kDomain = 57;

// Localhost only (the loopback interface, unicast discovery), unless the caller chose.
const bool kLocalhost = [] {
    setenv("CYCLONEDDS_URI",
           "<CycloneDDS><Domain Id=\"any\"><General><Interfaces><NetworkInterface name=\"lo\"/>"
           "</Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery>"
           "<ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>30"
           "</MaxAutoParticipantIndex><Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery>"
           "</Domain></CycloneDDS>",
           0);
    return true;
}();

TEST(Ros2Names, TypeNamesAreRmwCyclonedds) {
    EXPECT_STREQ(sensor_msgs_msg_dds__PointCloud2__desc.m_typename,
                 "sensor_msgs::msg::dds_::PointCloud2_");
    EXPECT_STREQ(sensor_msgs_msg_dds__Imu__desc.m_typename, "sensor_msgs::msg::dds_::Imu_");
    EXPECT_STREQ(nav_msgs_msg_dds__Odometry__desc.m_typename, "nav_msgs::msg::dds_::Odometry_");
    EXPECT_STREQ(tf2_msgs_msg_dds__TFMessage__desc.m_typename, "tf2_msgs::msg::dds_::TFMessage_");
    EXPECT_STREQ(rosgraph_msgs_msg_dds__Clock__desc.m_typename, "rosgraph_msgs::msg::dds_::Clock_");
    // Key-less: one instance per topic, as every ROS 2 message.
    EXPECT_EQ(nav_msgs_msg_dds__Odometry__desc.m_nkeys, 0u);
    EXPECT_EQ(sensor_msgs_msg_dds__PointCloud2__desc.m_nkeys, 0u);
}

TEST(Ros2Names, TopicsArePrefixedRt) {
    EXPECT_EQ(DdsTopicName("/dorado/smoothed_odom"), "rt/dorado/smoothed_odom");
    EXPECT_EQ(DdsTopicName("/tf"), "rt/tf");
    EXPECT_EQ(DdsTopicName("doppler_odom"), "rt/doppler_odom");  // relative: the root namespace
    for (const char *bad : {"", "/", "/a//b", "/a/", "/a b", "/a-b"})
        EXPECT_THROW((void)DdsTopicName(bad), std::invalid_argument) << bad;
}

struct ExpectedQos {
    QosProfile profile;
    dds_reliability_kind_t reliability;
    dds_durability_kind_t durability;
    int32_t depth;
};

TEST(Ros2Qos, ProfilesAreRmws) {
    // rmw/qos_profiles.h: sensor data = best effort, keep last 5; default = reliable, keep last
    // 10; tf2_ros: /tf reliable keep last 100, /tf_static transient local keep last 1; rclcpp's
    // ClockQoS: best effort keep last 1.
    const ExpectedQos expected[] = {
        {QosProfile::kSensorData, DDS_RELIABILITY_BEST_EFFORT, DDS_DURABILITY_VOLATILE, 5},
        {QosProfile::kDefault, DDS_RELIABILITY_RELIABLE, DDS_DURABILITY_VOLATILE, 10},
        {QosProfile::kTf, DDS_RELIABILITY_RELIABLE, DDS_DURABILITY_VOLATILE, 100},
        {QosProfile::kTransientLocal, DDS_RELIABILITY_RELIABLE, DDS_DURABILITY_TRANSIENT_LOCAL, 1},
        {QosProfile::kClock, DDS_RELIABILITY_BEST_EFFORT, DDS_DURABILITY_VOLATILE, 1}};
    for (const ExpectedQos &e : expected) {
        const QosPtr qos = MakeQos(e.profile);
        dds_reliability_kind_t reliability;
        dds_duration_t blocking;
        dds_durability_kind_t durability;
        dds_history_kind_t history;
        int32_t depth;
        uint32_t n = 0;
        dds_data_representation_id_t *representations = nullptr;
        ASSERT_TRUE(dds_qget_reliability(qos.get(), &reliability, &blocking));
        ASSERT_TRUE(dds_qget_durability(qos.get(), &durability));
        ASSERT_TRUE(dds_qget_history(qos.get(), &history, &depth));
        ASSERT_TRUE(dds_qget_data_representation(qos.get(), &n, &representations));
        EXPECT_EQ(reliability, e.reliability);
        EXPECT_EQ(durability, e.durability);
        EXPECT_EQ(history, DDS_HISTORY_KEEP_LAST);
        EXPECT_EQ(depth, e.depth);
        ASSERT_EQ(n, 1u);
        EXPECT_EQ(representations[0], DDS_DATA_REPRESENTATION_XCDR1);
        dds_free(representations);
    }
    dds_reliability_kind_t reliability;
    dds_duration_t blocking;
    int32_t depth;
    dds_history_kind_t history;
    const QosPtr deep = MakeQos(QosProfile::kSensorData, 100);
    ASSERT_TRUE(dds_qget_history(deep.get(), &history, &depth));
    ASSERT_TRUE(dds_qget_reliability(deep.get(), &reliability, &blocking));
    EXPECT_EQ(depth, 100);
    EXPECT_EQ(reliability, DDS_RELIABILITY_BEST_EFFORT);
}

TEST(Ros2Domain, FromRosDomainId) {
    const char *saved = std::getenv("ROS_DOMAIN_ID");
    const std::string keep = saved ? saved : "";
    unsetenv("ROS_DOMAIN_ID");
    EXPECT_EQ(DomainFromEnvironment(), 0u);
    setenv("ROS_DOMAIN_ID", "", 1);
    EXPECT_EQ(DomainFromEnvironment(), 0u);
    setenv("ROS_DOMAIN_ID", "42", 1);
    EXPECT_EQ(DomainFromEnvironment(), 42u);
    for (const char *bad : {"x", "-1", "233", "4 2", "1.5"}) {
        setenv("ROS_DOMAIN_ID", bad, 1);
        try {
            (void)DomainFromEnvironment();
            ADD_FAILURE() << bad;
        } catch (const std::invalid_argument &e) {
            EXPECT_NE(std::string(e.what()).find("ROS_DOMAIN_ID"), std::string::npos);
        }
    }
    if (saved)
        setenv("ROS_DOMAIN_ID", keep.c_str(), 1);
    else
        unsetenv("ROS_DOMAIN_ID");
}

// Waits until the reader has a sample (or 5 s) and takes its bytes.
std::vector<uint8_t> TakeOne(dds_entity_t reader) {
    for (int i = 0; i < 500; ++i) {
        auto taken = TakeSerialized(reader);
        if (!taken.empty()) return taken.front();
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return {};
}

// A writer and a reader (without a listener: the test takes) of one type on a topic, matched.
struct Loopback {
    Loopback(Participant &participant, const std::string &topic, const dds_topic_descriptor_t &type)
        : writer(participant, topic, type, QosProfile::kDefault),
          reader(dds_create_reader(participant.get(), participant.Topic(topic, type),
                                   MakeQos(QosProfile::kDefault).get(), nullptr)) {
        for (int i = 0; i < 500 && writer.Subscribers() == 0; ++i)
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    // The bytes of one sample as Cyclone serializes it.
    std::vector<uint8_t> RoundTrip(const void *sample) {
        writer.Write(sample);
        return TakeOne(reader.get());
    }
    Writer writer;
    Entity reader;
};

TEST(Ros2Cdr, OdometryTheNodeWritesDecodesWithTheRosbag2Codec) {
    Participant participant(kDomain);
    Loopback loopback(participant, "/dorado/test_odom", nav_msgs_msg_dds__Odometry__desc);
    ros_node::OdometryOutput odometry;
    odometry.stamp_ns = 1690000001234567891LL;
    odometry.frame_id = "map";
    odometry.child_frame_id = "base_link";
    odometry.T_frame_child = Eigen::Translation3d(1.5, -2.25, 0.125) *
                             Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized());
    for (int i = 0; i < 36; ++i) odometry.pose_covariance(i / 6, i % 6) = 0.01 * i;
    odometry.twist_child.v_base_mps = Eigen::Vector3d(3, 0.1, 0);
    const nav_msgs_msg_dds__Odometry_ msg = OdometryOf(odometry);
    const std::vector<uint8_t> bytes = loopback.RoundTrip(&msg);
    ASSERT_GT(bytes.size(), 4u);
    EXPECT_EQ(bytes[0], 0x00);  // CDR_LE: plain CDR (XCDR1), little-endian, as rosbag2 stores
    EXPECT_EQ(bytes[1], 0x01);
    const io::CdrPose pose = io::DecodeOdometryCdr(bytes);
    EXPECT_EQ(pose.header.stamp_ns, odometry.stamp_ns);
    EXPECT_EQ(pose.header.frame_id, "map");
    EXPECT_EQ(pose.child_frame_id, "base_link");
    EXPECT_EQ(pose.position, odometry.T_frame_child.translation());
    EXPECT_LT((pose.orientation.toRotationMatrix() - odometry.T_frame_child.linear()).norm(),
              1e-15);
    for (int i = 0; i < 36; ++i) EXPECT_EQ(pose.covariance[i], 0.01 * i);
}

// The recorded bytes and the republished ones: the same up to Cyclone's padding of the end to
// 4 bytes (XCDR: the encapsulation's options say how many).
void ExpectSameCdr(const std::vector<uint8_t> &recorded, const std::vector<uint8_t> &republished,
                   const std::string &what) {
    ASSERT_GE(republished.size(), recorded.size()) << what;
    ASSERT_LT(republished.size(), recorded.size() + 4) << what;
    EXPECT_EQ(republished[0], recorded[0]) << what;
    EXPECT_EQ(republished[1], recorded[1]) << what;
    EXPECT_EQ((republished[3] & 0x3u), republished.size() - recorded.size()) << what;
    EXPECT_TRUE(std::equal(recorded.begin() + 4, recorded.end(), republished.begin() + 4)) << what;
    for (std::size_t i = recorded.size(); i < republished.size(); ++i) EXPECT_EQ(republished[i], 0);
}

TEST(Ros2Cdr, RecordedMessagesRepublishWithTheirBytes) {
    const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) /
                                      ("dorado_ros2_cdr_" + std::to_string(getpid()));
    const std::string cmd = std::string(DORADO_SYSTEM_PYTHON) + " " + DORADO_SOURCE_DIR +
                            "/tests/io/make_ros2_bags.py fixtures " + dir.string();
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    const std::string recording = (dir / "known.db3").string();
    const auto messages = io::OpenRecordedMessages(recording, {});
    Participant participant(kDomain);
    Loopback clouds(participant, "/test/cloud", sensor_msgs_msg_dds__PointCloud2__desc);
    Loopback imus(participant, "/test/imu", sensor_msgs_msg_dds__Imu__desc);
    int compared_clouds = 0, compared_imus = 0, big_endian = 0;
    io::RecordedMessage m;
    while (messages->Next(m)) {
        ASSERT_TRUE(m.problem.empty()) << m.problem;
        const bool little = m.data[1] == 0x01;
        if (m.topic == "/hugin_raf_1/radar_data") {
            const io::CdrPointCloud2 cloud = io::DecodePointCloud2Cdr(m.data);
            std::vector<sensor_msgs_msg_dds__PointField_> fields;
            const sensor_msgs_msg_dds__PointCloud2_ msg = CloudOf(cloud, fields);
            const std::vector<uint8_t> bytes = clouds.RoundTrip(&msg);
            if (little) {
                ExpectSameCdr(m.data, bytes, "cloud");
                ++compared_clouds;
            } else {  // a big-endian recording comes back little-endian, the same values
                const io::CdrPointCloud2 back = io::DecodePointCloud2Cdr(bytes);
                EXPECT_EQ(back.header.stamp_ns, cloud.header.stamp_ns);
                ASSERT_EQ(back.cloud.data_size, cloud.cloud.data_size);
                EXPECT_TRUE(std::equal(cloud.cloud.data, cloud.cloud.data + cloud.cloud.data_size,
                                       back.cloud.data));
                ++big_endian;
            }
        } else if (m.topic == "/imu") {
            const io::CdrImu imu = io::DecodeImuCdr(m.data);  // the message borrows its frame_id
            const sensor_msgs_msg_dds__Imu_ msg = ImuOf(imu);
            ExpectSameCdr(m.data, imus.RoundTrip(&msg), "imu");
            ++compared_imus;
        }
    }
    EXPECT_EQ(compared_clouds, 4);  // the recording's five scans, one big-endian
    EXPECT_EQ(big_endian, 1);
    EXPECT_EQ(compared_imus, 20);
    std::filesystem::remove_all(dir);
}

TEST(Ros2Domain, TwoDomainsDoNotSeeEachOther) {
    Participant a(kDomain), b(kDomain + 1);
    Writer writer(a, "/test/domains", nav_msgs_msg_dds__Odometry__desc, QosProfile::kDefault);
    int heard_b = 0;
    RawReader reader_b(b, "/test/domains", nav_msgs_msg_dds__Odometry__desc, QosProfile::kDefault,
                       10, [&](std::vector<uint8_t>) { ++heard_b; });
    std::this_thread::sleep_for(std::chrono::milliseconds(500));  // discovery on localhost
    EXPECT_EQ(writer.Subscribers(), 0);
    EXPECT_EQ(reader_b.Publishers(), 0);
    Participant a2(kDomain);
    RawReader reader_a(a2, "/test/domains", nav_msgs_msg_dds__Odometry__desc, QosProfile::kDefault,
                       10, [](std::vector<uint8_t>) {});
    for (int i = 0; i < 500 && writer.Subscribers() == 0; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_EQ(writer.Subscribers(), 1);  // the same domain does
    EXPECT_EQ(heard_b, 0);
}

}  // namespace
}  // namespace dorado::ros2
