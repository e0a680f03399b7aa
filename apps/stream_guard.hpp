#pragma once
/// @file stream_guard.hpp
/// A long command (odometry, map) reading a dataset stops early in two ways that must not lose the
/// scans already processed: the user presses Ctrl-C (or the job is sent SIGTERM), or the reader
/// meets damage it cannot step over (a bag cut off mid-chunk). StreamGuard turns both into the end
/// of the stream with a reason; the command then writes its results and exits non-zero.

#include <string>

#include "dorado/io/dataset.hpp"

namespace dorado::apps {

/// While it lives, SIGINT and SIGTERM are caught instead of ending the process: the first signal
/// is kept (caught()); the handler is then reset, so a second signal ends the process at once.
class SignalCatcher {
  public:
    SignalCatcher();
    /// Restores the previous handlers.
    ~SignalCatcher();
    SignalCatcher(const SignalCatcher &) = delete;
    SignalCatcher &operator=(const SignalCatcher &) = delete;
    /// The signal caught (SIGINT, SIGTERM), 0 while none was.
    [[nodiscard]] int caught() const;
};

class StreamGuard {
  public:
    /// Catches SIGINT/SIGTERM (SignalCatcher): the first signal asks the loop to stop after the
    /// current scan.
    StreamGuard();

    /// reader.Next(event), or false when the stream ends early: at a signal or at a DatasetError
    /// thrown by the reader (the reason is kept, see stopped()).
    bool Next(io::DatasetReader &reader, io::DatasetEvent &event);

    /// Why the stream ended early; empty when it ran to its end.
    [[nodiscard]] const std::string &stopped() const { return reason_; }
    /// The exit code for an early end: 130 after a signal (as a shell reports SIGINT), 1 otherwise.
    [[nodiscard]] int exit_code() const { return signalled_ ? 130 : 1; }

    /// Throws io::DatasetError "SOURCE: no usable radar scan" (with the reason the stream ended
    /// early, if it did) when `scans_used` is 0: there are no results to write.
    void ThrowIfNoScanUsed(std::size_t scans_used, const std::string &source) const;

    /// Throws after the results were written, when the stream ended early: the message names the
    /// reason and where the results of the scans before it are.
    void ThrowIfStopped(const std::string &command, std::size_t scans,
                        const std::string &out_dir) const;

  private:
    SignalCatcher signals_;
    std::string reason_;
    bool signalled_ = false;
    /// Test hook: with DORADO_TEST_SIGINT_AFTER_SCANS=N in the environment, the process sends
    /// itself a real SIGINT after the N-th radar scan (end-to-end tests of the interrupt path).
    long sigint_after_scans_ = -1;
    long scans_seen_ = 0;
};

/// The number of radar messages in a bag (for the progress display; 0 for a folder), after
/// checking that the IMU topic holds samples when `needs_imu`: a topic registered in the bag with
/// no message throws io::DatasetError naming the topic, its key and `who_needs_it`.
[[nodiscard]] std::size_t CountRadarMessages(const io::DatasetConfig &dataset, bool needs_imu,
                                             const std::string &who_needs_it);

/// Thrown by StreamGuard::ThrowIfStopped; main() prints it and exits with exit_code.
class StoppedEarly : public std::runtime_error {
  public:
    StoppedEarly(const std::string &what, int exit_code)
        : std::runtime_error(what), exit_code_(exit_code) {}
    [[nodiscard]] int exit_code() const { return exit_code_; }

  private:
    int exit_code_;
};

}  // namespace dorado::apps
