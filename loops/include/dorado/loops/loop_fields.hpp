#pragma once
/// @file loop_fields.hpp
/// The loop closure's configurable fields, listed once (core/config_fields.hpp): keys as in
/// configs/mapper.yaml's `loop_closure:` section. The defaults are the structs'.

#include "dorado/core/config_fields.hpp"
#include "dorado/loops/loop_closer.hpp"

namespace dorado::loops {

template <typename Visitor>
void VisitFields(LoopClosureConfig &c, Visitor &&v) {
    v("enabled", c.enabled,
      "close loops: submaps, place recognition, verification and a pose graph over the written "
      "poses; trajectory.tum and the map are corrected (`dorado map --no-loops` turns it off)");
    v("submap_length_m", c.submap.length_m, "a submap ends after this much path [m]");
    v("submap_turn_deg", c.submap.turn_deg, "... or this much change of heading [deg]");
    v("submap_voxel_m", c.submap.voxel_m,
      "a submap's points for recognition and verification: one per voxel of this size [m]");
    v("min_loop_path_m", c.min_loop_path_m, "path between two submaps for a loop between them [m]");
    v("place_radius_m", c.place_radius_m,
      "submap centres this close share a place: the drift gate's radius without drift [m]");
    v("gate_sigmas", c.gate_sigmas,
      "the drift gate adds this many sigmas of the odometry chain's position uncertainty");
    v("max_verifications", c.max_verifications,
      "descriptor matches verified by registration per submap (most inliers first)");
    v("max_consistency_chi2", c.max_consistency_chi2,
      "largest squared Mahalanobis distance of a loop from the odometry chain (6 dof)");
    v("place_image_cell_m", c.place.image_cell_m, "bird's-eye density image resolution [m]");
    v("place_image_radius_m", c.place.image_radius_m, "half the image's side [m]");
    v("place_max_features", c.place.max_features, "ORB corners per image");
    v("place_ratio_test", c.place.ratio_test, "Lowe's ratio test of the descriptor matches");
    v("place_ransac_threshold_m", c.place.ransac_threshold_m, "RANSAC inlier distance [m]");
    v("place_min_inliers", c.place.min_inliers, "RANSAC inliers for a place match");
    v("place_max_scale_error", c.place.max_scale_error,
      "largest |scale - 1| of the RANSAC similarity");
    v("verify_max_iterations", c.verification.max_iterations, "registration iterations");
    v("verify_initial_threshold_m", c.verification.initial_threshold_m,
      "correspondence distance of the first iterations [m]");
    v("verify_final_threshold_m", c.verification.final_threshold_m,
      "... shrinking to this one, also the overlap's distance [m]");
    v("verify_point_sigma_m", c.verification.point_sigma_m, "a submap point's noise [m]");
    v("verify_plane_flatness", c.verification.plane_flatness,
      "GICP eigenvalue of a neighbourhood's normal axis");
    v("verify_cluster_m", c.verification.cluster_m,
      "residuals in one cell of this size count as one measurement [m]");
    v("verify_min_overlap", c.verification.min_overlap,
      "fraction of the query's points with a match within verify_final_threshold_m");
    v("verify_min_correspondences", c.verification.min_correspondences, "matches at the end");
    v("verify_max_rms_m", c.verification.max_rms_m, "their largest RMS distance [m]");
    v("verify_min_observability", c.verification.min_observability,
      "smallest / largest eigenvalue of the information over x, y and yaw (at the points' "
      "radius)");
    v("verify_floor_sigma_translation_m", c.verification.floor_sigma_translation_m,
      "added to a loop's covariance [m]");
    v("verify_floor_sigma_rotation_rad", c.verification.floor_sigma_rotation_rad,
      "added to a loop's covariance [rad]");
    v("graph_loop_loss_scale", c.graph.loop_loss_scale, "Cauchy scale of a loop edge [sigmas]");
    v("graph_switch_prior_sigma", c.graph.switch_prior_sigma,
      "a loop edge's switch prior: lower turns disagreeing edges off sooner");
    v("graph_max_iterations", c.graph.max_iterations, "Ceres iterations of a graph solve");
}

}  // namespace dorado::loops
