#include "dorado/core/imu.hpp"

#include <algorithm>

#include <limits>

namespace dorado {

Eigen::Vector3d MeanAngularVelocity(const std::vector<ImuSample> &samples, int64_t t0_ns,
                                    int64_t t1_ns) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int count = 0;
    for (const auto &s : samples) {
        if (s.stamp_ns < t0_ns || s.stamp_ns > t1_ns) continue;
        sum += s.omega_imu_radps;
        ++count;
    }
    if (count == 0) return Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    return sum / count;
}

void ImuWindow::Add(const ImuSample &sample) {
    if (!sample.omega_imu_radps.allFinite() || !sample.accel_imu_mps2.allFinite()) return;
    samples_.push_back(sample);
    newest_stamp_ns_ = std::max(newest_stamp_ns_, sample.stamp_ns);
}

std::vector<ImuSample> ImuWindow::Between(int64_t t0_ns, int64_t t1_ns) const {
    std::vector<ImuSample> out;
    for (const auto &s : samples_) {
        if (s.stamp_ns > t0_ns && s.stamp_ns <= t1_ns) out.push_back(s);
    }
    return out;
}

Eigen::Vector3d ImuWindow::MeanGyro(int64_t t0_ns, int64_t t1_ns) const {
    return MeanAngularVelocity(samples_, t0_ns + 1, t1_ns);
}

void ImuWindow::DropUpTo(int64_t t_ns) {
    samples_.erase(std::remove_if(samples_.begin(), samples_.end(),
                                  [&](const ImuSample &s) { return s.stamp_ns <= t_ns; }),
                   samples_.end());
}

}  // namespace dorado
