#pragma once
/// @file reference_path.hpp
/// The dataset's reference trajectory (its ground truth) drawn beside the estimate in map.png:
/// put into the estimate's world frame by the pose at the estimate's first stamp.

#include <Eigen/Core>
#include <vector>

#include "dorado/core/trajectory.hpp"
#include "dorado/io/dataset_config.hpp"

namespace dorado::apps {

/// The reference's positions over the estimate's time span, in the estimate's world:
/// p = T_est(t0) * T_ref(t0)^-1 * p_ref(t), t0 the first estimate stamp the reference covers.
/// Empty when the reference does not cover any estimate stamp.
[[nodiscard]] std::vector<Eigen::Vector3d> AlignedReferencePath(const Trajectory &reference,
                                                                const Trajectory &estimate);

/// The dataset's ground truth (io::LoadGroundTruth) aligned to the estimate; empty when the
/// dataset has none. A reference that cannot be read is a warning on stderr naming the file, not
/// an error: the map run's outputs do not depend on it.
[[nodiscard]] std::vector<Eigen::Vector3d> ReferencePath(const io::DatasetConfig &dataset,
                                                         const Trajectory &estimate);

}  // namespace dorado::apps
