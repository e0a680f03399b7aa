// A ROS 2 subscriber for dorado_ros2's tests, without ROS 2: records nav_msgs/msg/Odometry topics
// (decoded with dorado_io's codec, the rosbag2 reader's) and the publications it discovers on
// the domain (ROS_DOMAIN_ID), until SIGINT or SIGTERM.
//   dds_recorder OUT_DIR TOPIC...
// OUT_DIR/odometry.txt: "topic stamp_ns frame child x y z qx qy qz qw c0 .. c35" per message;
// OUT_DIR/publications.txt: "topic type reliability durability history depth" per publication
// (the DDS names: rt/..., <package>::msg::dds_::<Type>_). Prints "ready" once subscribed.
#include <dds/dds.h>

#include <csignal>
#include <cstdio>
#include <ctime>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "dorado/io/cdr_messages.hpp"
#include "dorado/ros2/dds.hpp"
#include "ros2_messages.h"

namespace {

volatile std::sig_atomic_t g_stop = 0;
void OnSignal(int) {
    g_stop = 1;
}

std::mutex g_mutex;

void RecordPublications(dds_entity_t reader, FILE *out, std::set<std::string> &seen) {
    void *samples[16] = {};
    dds_sample_info_t infos[16];
    const int n = dds_take(reader, samples, infos, 16, 16);
    for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        const auto *p = static_cast<const dds_builtintopic_endpoint_t *>(samples[i]);
        dds_reliability_kind_t reliability = DDS_RELIABILITY_BEST_EFFORT;
        dds_durability_kind_t durability = DDS_DURABILITY_VOLATILE;
        dds_history_kind_t history = DDS_HISTORY_KEEP_LAST;
        int32_t depth = 0;
        dds_duration_t blocking;
        dds_qget_reliability(p->qos, &reliability, &blocking);
        dds_qget_durability(p->qos, &durability);
        dds_qget_history(p->qos, &history, &depth);
        const std::string line =
            std::string(p->topic_name) + " " + p->type_name + " " +
            (reliability == DDS_RELIABILITY_RELIABLE ? "reliable" : "best_effort") + " " +
            (durability == DDS_DURABILITY_TRANSIENT_LOCAL ? "transient_local"
             : durability == DDS_DURABILITY_VOLATILE      ? "volatile"
                                                          : "other") +
            " " + (history == DDS_HISTORY_KEEP_LAST ? "keep_last" : "keep_all") + " " +
            std::to_string(depth);
        if (seen.insert(line).second) {
            std::fprintf(out, "%s\n", line.c_str());
            std::fflush(out);
        }
    }
    if (n > 0) dds_return_loan(reader, samples, n);
}

}  // namespace

int main(int argc, char **argv) {
    using namespace dorado;
    if (argc < 3) {
        std::fprintf(stderr, "usage: dds_recorder OUT_DIR TOPIC...\n");
        return 2;
    }
    const std::string dir = argv[1];
    FILE *odometry = std::fopen((dir + "/odometry.txt").c_str(), "w");
    FILE *publications = std::fopen((dir + "/publications.txt").c_str(), "w");
    if (!odometry || !publications) {
        std::fprintf(stderr, "dds_recorder: cannot write in %s\n", dir.c_str());
        return 1;
    }
    std::signal(SIGINT, OnSignal);
    std::signal(SIGTERM, OnSignal);
    try {
        ros2::Participant participant(ros2::DomainFromEnvironment());
        std::vector<std::unique_ptr<ros2::RawReader>> readers;
        for (int i = 2; i < argc; ++i) {
            const std::string topic = argv[i];
            readers.push_back(std::make_unique<ros2::RawReader>(
                participant, topic, nav_msgs_msg_dds__Odometry__desc, ros2::QosProfile::kDefault,
                100000, [topic, odometry](std::vector<uint8_t> bytes) {
                    const io::CdrPose pose = io::DecodeOdometryCdr(bytes);
                    std::lock_guard<std::mutex> lock(g_mutex);
                    std::fprintf(odometry,
                                 "%s %lld %s %s %.12g %.12g %.12g %.12g %.12g %.12g %.12g",
                                 topic.c_str(), static_cast<long long>(pose.header.stamp_ns),
                                 pose.header.frame_id.c_str(), pose.child_frame_id.c_str(),
                                 pose.position.x(), pose.position.y(), pose.position.z(),
                                 pose.orientation.x(), pose.orientation.y(), pose.orientation.z(),
                                 pose.orientation.w());
                    for (double c : pose.covariance) std::fprintf(odometry, " %.9g", c);
                    std::fprintf(odometry, "\n");
                    std::fflush(odometry);
                }));
        }
        const dds_entity_t builtin = dds_create_reader(
            participant.get(), DDS_BUILTIN_TOPIC_DCPSPUBLICATION, nullptr, nullptr);
        std::set<std::string> seen;
        std::printf("ready\n");
        std::fflush(stdout);
        while (!g_stop) {
            RecordPublications(builtin, publications, seen);
            struct timespec pause {
                0, 20000000
            };
            nanosleep(&pause, nullptr);
        }
        RecordPublications(builtin, publications, seen);
    } catch (const std::exception &e) {
        std::fprintf(stderr, "dds_recorder: error: %s\n", e.what());
        return 1;
    }
    std::fclose(odometry);
    std::fclose(publications);
    return 0;
}
