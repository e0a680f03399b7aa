#pragma once
/// @file covariance_table.hpp
/// `dorado map`'s covariance.csv: per written scan, the smoother's inputs (the motion prior and
/// the registration) and its output (the written pose), each with its covariance, so that the
/// prior alone, the registration alone and the written pose can be compared in one run
/// (benchmarks/mapping/fusion_nees.py scores them).
///
/// Columns: t, status (first_scan | fused | fallback: registered and smoothed, or nothing to
/// register), then for each of `fused`, `registration`, `prior`: the pose (x y z qx qy qz qw,
/// world frame; `fused` is trajectory.tum's written pose) and the 21 upper-triangle entries c_ij of
/// its 6x6 covariance, i <= j over the axes x y z rx ry rz of the right perturbation xi = [rho;
/// phi] in that pose's base frame (T_true = T ExpSE3(xi)). `fused`: the covariance of the motion
/// from the previous written pose; `prior`: of the prior's motion from the previous scan's newest
/// pose; `registration`: the registration's own given the map. The registration columns are empty
/// when there was no registration (first scan, fallback).

#include <string>

#include "dorado/frontend/radar_front_end.hpp"

namespace dorado::apps {

class CovarianceTable {
  public:
    CovarianceTable();
    /// Records one written scan of the mapper.
    void Add(const mapping::WrittenPose &written);
    [[nodiscard]] const std::string &csv() const { return csv_; }

  private:
    std::string csv_;
};

}  // namespace dorado::apps
