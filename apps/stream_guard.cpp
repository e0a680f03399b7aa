#include "stream_guard.hpp"

#include <csignal>
#include <cstdlib>

namespace dorado::apps {

namespace {

volatile std::sig_atomic_t g_signal = 0;

extern "C" void OnSignal(int signal_number) {
    g_signal = signal_number;
    std::signal(signal_number, SIG_DFL);  // a second Ctrl-C ends the process at once
}

using Handler = void (*)(int);
Handler g_previous_int = SIG_DFL, g_previous_term = SIG_DFL;

}  // namespace

SignalCatcher::SignalCatcher() {
    g_signal = 0;
    g_previous_int = std::signal(SIGINT, OnSignal);
    g_previous_term = std::signal(SIGTERM, OnSignal);
}

SignalCatcher::~SignalCatcher() {
    std::signal(SIGINT, g_previous_int);
    std::signal(SIGTERM, g_previous_term);
}

int SignalCatcher::caught() const {
    return g_signal;
}

StreamGuard::StreamGuard() {
    if (const char *hook = std::getenv("DORADO_TEST_SIGINT_AFTER_SCANS"))
        sigint_after_scans_ = std::strtol(hook, nullptr, 10);
}

bool StreamGuard::Next(io::DatasetReader &reader, io::DatasetEvent &event) {
    if (!reason_.empty()) return false;
    if (const int signal_number = signals_.caught(); signal_number != 0) {
        signalled_ = true;
        reason_ = signal_number == SIGINT ? "interrupted (SIGINT)" : "terminated (SIGTERM)";
        return false;
    }
    try {
        const bool more = reader.Next(event);
        if (more && event.kind == io::DatasetEvent::Kind::kRadarScan &&
            ++scans_seen_ == sigint_after_scans_)
            std::raise(SIGINT);  // handled by OnSignal: this scan is still processed
        return more;
    } catch (const io::DatasetError &e) {
        reason_ = e.what();
        return false;
    }
}

void StreamGuard::ThrowIfNoScanUsed(std::size_t scans_used, const std::string &source) const {
    if (scans_used > 0) return;
    throw io::DatasetError(source + ": no usable radar scan" +
                           (reason_.empty() ? "" : " before: " + reason_));
}

void StreamGuard::ThrowIfStopped(const std::string &command, std::size_t scans,
                                 const std::string &out_dir) const {
    if (reason_.empty()) return;
    throw StoppedEarly(command + " stopped early after " + std::to_string(scans) +
                           " scans: " + reason_ + "; the results of those scans are in " + out_dir,
                       exit_code());
}

std::size_t CountRadarMessages(const io::DatasetConfig &dataset, bool needs_imu,
                               const std::string &who_needs_it) {
    std::size_t radar_messages = 0;
    if (dataset.reader != io::ReaderKind::kRosbag) return radar_messages;
    for (const auto &t : io::ListTopics(dataset)) {
        if (t.topic == dataset.rosbag.radar_topic) radar_messages = t.messages;
        if (needs_imu && t.topic == dataset.rosbag.imu_topic && t.messages == 0) {
            throw io::DatasetError(dataset.rosbag.path + ": topic '" + t.topic +
                                   "' (rosbag.imu_topic) has no messages; " + who_needs_it +
                                   " needs IMU samples");
        }
    }
    return radar_messages;
}

}  // namespace dorado::apps
