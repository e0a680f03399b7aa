#include "loop_worker.hpp"

namespace dorado::ros_node {

LoopWorker::LoopWorker(const loops::LoopClosureConfig &config)
    : closer_(config), thread_([this] { Run(); }) {}

LoopWorker::~LoopWorker() {
    Stop();
}

void LoopWorker::Stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
}

void LoopWorker::Push(std::vector<mapping::WrittenPose> written) {
    if (written.empty()) return;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (mapping::WrittenPose &pose : written) queue_.push_back(std::move(pose));
    }
    wake_.notify_one();
}

Eigen::Isometry3d LoopWorker::Correction() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return correction_;
}

int LoopWorker::loops() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return loops_;
}

void LoopWorker::Run() {
    for (;;) {
        mapping::WrittenPose pose;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
            if (stop_) return;
            pose = std::move(queue_.front());
            queue_.pop_front();
        }
        const loops::LoopStep step = closer_.Add(pose);  // the slow part, outside the lock
        if (!step.submap_closed) continue;
        const Eigen::Isometry3d correction = closer_.LatestCorrection();
        const int loops = closer_.loops_accepted();
        std::lock_guard<std::mutex> lock(mutex_);
        correction_ = correction;
        loops_ = loops;
    }
}

}  // namespace dorado::ros_node
