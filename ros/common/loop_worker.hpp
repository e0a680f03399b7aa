#pragma once
/// @file loop_worker.hpp
/// Loop closure beside the live node's scan worker: the written poses are handed over (a queue,
/// never a wait on the closer) and a thread of its own runs loops::LoopCloser on them (submaps,
/// detection, verification, the graph solve). The newest correction is read by the scan worker
/// when it publishes map -> odom: a copy under a short lock, so a scan never waits for a solve.

#include <Eigen/Geometry>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

#include "dorado/loops/loop_closer.hpp"

namespace dorado::ros_node {

class LoopWorker {
  public:
    explicit LoopWorker(const loops::LoopClosureConfig &config);
    ~LoopWorker();
    LoopWorker(const LoopWorker &) = delete;
    LoopWorker &operator=(const LoopWorker &) = delete;

    /// Queues written poses (in order) for the closer.
    void Push(std::vector<mapping::WrittenPose> written);
    /// The correction of the newest pose the closer has seen: corrected map pose =
    /// Correction() * the mapper's pose (identity until a loop is closed).
    [[nodiscard]] Eigen::Isometry3d Correction() const;
    /// Loops accepted so far.
    [[nodiscard]] int loops() const;
    /// Stops the thread (poses still queued are not processed).
    void Stop();

  private:
    void Run();

    loops::LoopCloser closer_;  // the thread's alone
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<mapping::WrittenPose> queue_;
    Eigen::Isometry3d correction_ = Eigen::Isometry3d::Identity();
    int loops_ = 0;
    bool stop_ = false;
    std::thread thread_;
};

}  // namespace dorado::ros_node
