#pragma once
/// @file covariance_table.hpp
/// `dorado map`'s covariance.csv: per scan, the three estimates of the new pose that the
/// refinement fuses and their covariances, so that the prior alone, the registration alone and the
/// fused pose can be compared in one run (benchmarks/mapping/fusion_nees.py scores them).
///
/// Columns: t, status (first_scan | fused | unrefined | fallback; unrefined: registered but the
/// refinement failed, the covariance is the prior's), then for each of
/// `fused`, `registration`, `prior`: the pose (x y z qx qy qz qw, world frame, the fused one is
/// trajectory.tum's) and the 21 upper-triangle entries c_ij of its 6x6 covariance, i <= j over the
/// axes x y z rx ry rz of the right perturbation xi = [rho; phi] in that pose's base frame
/// (T_true = T ExpSE3(xi)). Each is the covariance given the map and the previous pose: the
/// uncertainty of this scan's motion relative to them. The registration columns are empty when
/// there was no registration (first scan, fallback).

#include <string>

#include "dorado/frontend/radar_front_end.hpp"

namespace dorado::apps {

class CovarianceTable {
  public:
    CovarianceTable();
    /// Records one accepted scan of the mapper.
    void Add(const frontend::FrontEndResult &result);
    [[nodiscard]] const std::string &csv() const { return csv_; }

  private:
    std::string csv_;
};

}  // namespace dorado::apps
