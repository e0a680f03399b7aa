#include "covariance_table.hpp"

#include <cstdio>

#include "dorado/core/time.hpp"

namespace dorado::apps {
namespace {

constexpr const char *kAxes[] = {"x", "y", "z", "rx", "ry", "rz"};

std::string Header() {
    std::string header = "t,status";
    for (const char *source : {"fused", "registration", "prior"}) {
        for (const char *p : {"x", "y", "z", "qx", "qy", "qz", "qw"})
            header += std::string(",") + source + "_" + p;
        for (int i = 0; i < 6; ++i)
            for (int j = i; j < 6; ++j)
                header += std::string(",") + source + "_c_" + kAxes[i] + "_" + kAxes[j];
    }
    return header + "\n";
}

// 7 pose values and 21 covariance entries, each with a leading comma; empty fields when absent.
std::string Columns(const Eigen::Isometry3d *T, const Matrix6d &C) {
    if (T == nullptr) return std::string(28, ',');
    std::string out;
    char cell[40];
    const Eigen::Quaterniond q(T->linear());
    const double pose[] = {T->translation().x(),
                           T->translation().y(),
                           T->translation().z(),
                           q.x(),
                           q.y(),
                           q.z(),
                           q.w()};
    for (double v : pose) {
        std::snprintf(cell, sizeof(cell), ",%.9g", v);
        out += cell;
    }
    for (int i = 0; i < 6; ++i)
        for (int j = i; j < 6; ++j) {
            std::snprintf(cell, sizeof(cell), ",%.6g", C(i, j));
            out += cell;
        }
    return out;
}

}  // namespace

CovarianceTable::CovarianceTable() : csv_(Header()) {}

void CovarianceTable::Add(const mapping::WrittenPose &w) {
    const char *status = w.first_scan ? "first_scan" : w.registered.valid ? "fused" : "fallback";
    char t[32];
    std::snprintf(t, sizeof(t), "%.9f", NanosToSeconds(w.stamp_ns));
    csv_ += std::string(t) + "," + status;
    csv_ += Columns(&w.T_world_base, w.covariance);
    csv_ +=
        Columns(w.registered.valid ? &w.registered.T_world_base : nullptr, w.registered.covariance);
    csv_ += Columns(w.first_scan ? nullptr : &w.prior.T_world_base, w.prior.covariance);
    csv_ += "\n";
}

}  // namespace dorado::apps
