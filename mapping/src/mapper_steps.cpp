// The steps of RadarMapper::Register around the registration: the prediction, the estimate
// (first scan, too few points, planar or 3-D), the smoother's step and the map update
// (mapper_state.hpp).
#include <chrono>
#include <cmath>
#include <string>
#include <utility>

#include "dorado/core/angles.hpp"
#include "dorado/core/time.hpp"
#include "ground_factor.hpp"
#include "mapper_state.hpp"
#include "planar_registration.hpp"
#include "pose_information.hpp"
#include "scan_points.hpp"

namespace dorado::mapping {

namespace {

using Clock = std::chrono::steady_clock;

// A planar registration as the mapper's estimate.
ScanEstimate EstimateOf(const PlanarRegistration &reg) {
    ScanEstimate out;
    out.cause = reg.cause;
    out.detail = reg.detail;
    out.observability = reg.observability;
    out.correspondences = reg.count;
    out.fitness_rms_m = reg.rms_m;
    out.alignment_ms = reg.alignment_ms;
    out.registration_ms = reg.registration_ms;
    out.refinement_ms = reg.refinement_ms;
    out.registered = reg.registered;
    out.T_world_base_aligned = reg.T_world_base_aligned;
    return out;
}

// The registered pose z against the prediction (P its covariance), with the registration's
// information w I (possibly singular: zero where the map does not observe): nu^T S^-1 nu with
// nu = Log(prediction^-1 z), S = P + (w I)^-1, S^-1 = w I - w I (P^-1 + w I)^-1 w I (zero along
// I's null space).
double InnovationMahalanobisSquared(const Vector6d &nu, const Matrix6d &P_inv, const Matrix6d &I,
                                    double w) {
    const Matrix6d wI = w * I;
    const Matrix6d S_inv = wI - wI * (P_inv + wI).ldlt().solve(wI);
    return nu.dot(S_inv * nu);
}

// The registration's weight: 1 when it agrees with the prediction within max_chi2; otherwise its
// information is scaled down until it does (its covariance inflated to explain the innovation),
// so that a wrong registration moves the pose by a few of the prediction's sigmas at most, and a
// right one against a wrong prediction still pulls it back over a few scans. Bisection on log w
// (the distance grows with w).
double RegistrationWeight(double m2, const Vector6d &nu, const Matrix6d &P_inv, const Matrix6d &I,
                          double max_chi2) {
    if (!(m2 > max_chi2)) return 1.0;
    double lo = -30.0, hi = 0.0;  // log w
    for (int i = 0; i < 40; ++i) {
        const double mid = 0.5 * (lo + hi);
        (InnovationMahalanobisSquared(nu, P_inv, I, std::exp(mid)) > max_chi2 ? hi : lo) = mid;
    }
    return std::exp(lo);
}

}  // namespace

RadarMapper::State::State(const MapperConfig &c, const Extrinsics &e)
    : config(c),
      extrinsics(e),
      map(c.map),
      movers(c.movers, c.map.voxel_size_m),
      smoother(c.smoother),
      threshold(c.initial_threshold_m, c.min_threshold_m, c.min_motion_m, c.max_range_m) {}

// A 2D radar's map lives in the plane: the prior's motion since the previous pose projected onto
// it (x, y and the rotation about the base's z axis), z, roll and pitch held. A 3-D gyro's roll and
// pitch rates (a car's body roll, sensor noise) would otherwise be integrated into every pose.
MotionPrior OnThePlane(const MotionPrior &prior, const Eigen::Isometry3d &T_world_base_last) {
    const Eigen::Isometry3d D_last_prior = T_world_base_last.inverse() * prior.T_world_base;
    Eigen::Isometry3d D_planar = Eigen::Isometry3d::Identity();
    D_planar.linear() =
        Eigen::AngleAxisd(RollPitchYaw(D_last_prior.linear()).z(), Eigen::Vector3d::UnitZ())
            .toRotationMatrix();
    D_planar.translation() << D_last_prior.translation().x(), D_last_prior.translation().y(), 0.0;
    MotionPrior planar = prior;
    planar.T_world_base = T_world_base_last * D_planar;
    return planar;
}

MotionPrior RadarMapper::State::Predict(const MotionPrior &prior) const {
    MotionPrior prediction = prior;
    if (!has_pose) return prediction;
    const Eigen::Isometry3d motion = T_world_base_last.inverse() * prior.T_world_base;
    prediction.T_world_base = T_world_base_last * motion;
    const Matrix6d Ad = AdjointSE3(motion.inverse());
    prediction.covariance = Ad * smoother.newest_covariance() * Ad.transpose() + prior.covariance;
    return prediction;
}

ScanEstimate RadarMapper::State::Estimate(const Eigen::Matrix3Xd &source_base,
                                          const std::vector<DopplerObservation> &doppler,
                                          const MotionPrior &prediction, const MapperInput &input,
                                          double threshold_m) {
    if (map.empty()) {  // the first scan starts the map at the prior, its origin
        ScanEstimate first;
        first.first_scan = true;
        return first;
    }
    const int source_points = static_cast<int>(source_base.cols());
    if (source_points < config.min_correspondences) {
        ScanEstimate too_few;
        too_few.cause = FallbackCause::kTooFewPoints;
        too_few.detail = std::to_string(source_points);
        return too_few;
    }
    if (planar)  // a 2D radar: x, y and yaw (planar_registration.cpp)
        return EstimateOf(RegisterPlanar(source_base, prediction, map, config, threshold_m));
    const GroundUp *ground = input.ground_base ? &*input.ground_base : nullptr;
    return RegisterToMap(source_base, doppler, prediction, input.dt_s, threshold_m, ground);
}

std::vector<WrittenPose> RadarMapper::State::Smooth(PendingScan scan, const MotionPrior &prior,
                                                    const MotionPrior &prediction,
                                                    const ScanEstimate &estimate,
                                                    const GroundUp *ground,
                                                    RegistrationResult &result) {
    SmootherScan in;
    in.stamp_ns = scan.written.stamp_ns;
    in.time_s = time_s;
    in.motion = has_pose ? T_world_base_last.inverse() * prior.T_world_base : prior.T_world_base;
    in.motion_covariance = prior.covariance;
    const RegisteredPose &registered = estimate.registered;
    if (!estimate.fallback() && !estimate.first_scan && registered.valid) {
        // A registration far from the prediction is down-weighted, not thrown away. Its distance
        // is the alignment's (the registration alone): the refined pose has the prediction in it.
        const Vector6d nu =
            LogSE3(prediction.T_world_base.inverse() * estimate.T_world_base_aligned);
        const Matrix6d P_inv = CovarianceFromInformation(prediction.covariance);
        result.prior_mahalanobis_squared =
            InnovationMahalanobisSquared(nu, P_inv, registered.information, 1.0);
        result.registration_weight =
            RegistrationWeight(result.prior_mahalanobis_squared, nu, P_inv, registered.information,
                               config.smoother.max_registration_chi2);
        in.T_world_base_registered = registered.T_world_base;
        in.registration_information = result.registration_weight * registered.information;
        // kiss-icp: the threshold adapts to how far registration corrected the prediction.
        threshold.Update(prediction.T_world_base.inverse() * registered.T_world_base);
    }
    if (ground != nullptr && has_pose &&
        GroundConsistent(*ground, prediction.T_world_base,
                         prediction.covariance.bottomRightCorner<3, 3>())) {
        in.ground_base = *ground;
        result.ground_used = true;
    }
    T_world_base_last = smoother.Add(in);
    has_pose = true;
    result.T_world_base = T_world_base_last;
    result.covariance = smoother.newest_covariance();

    scan.written.prior = prior;
    scan.written.registered = registered;
    scan.written.first_scan = estimate.first_scan;
    scan.written.registration_weight = result.registration_weight;
    scan.fallback = estimate.fallback();
    if (estimate.first_scan) {  // the origin starts the map at once: the next scans register to it
        scan.written.map_points_added_world =
            map.Update(T_world_base_last * scan.p_base, T_world_base_last.translation());
        T_world_base_last_keyframe = T_world_base_last;
        scan.written.map_updated = scan.in_map = true;
        map.BuildIndex();
    }
    pending.push_back(std::move(scan));
    return Write(smoother.TakeSmoothed(), result.times.map_update_ms);
}

void RadarMapper::State::DropFromPending(const std::vector<VoxelKey> &cells) {
    for (PendingScan &scan : pending) {
        if (!scan.in_map) continue;
        Eigen::Matrix3Xd &added = scan.written.map_points_added_world;
        Eigen::Index kept = 0;
        for (Eigen::Index i = 0; i < added.cols(); ++i)
            if (std::find(cells.begin(), cells.end(),
                          VoxelKeyOf(added.col(i), config.map.voxel_size_m)) == cells.end())
                added.col(kept++) = added.col(i);
        added.conservativeResize(3, kept);
    }
}

bool RadarMapper::State::IsKeyframe(const Eigen::Isometry3d &T_world_base) const {
    if (config.keyframe_distance_m <= 0.0 && config.keyframe_angle_deg <= 0.0) return true;
    const Eigen::Isometry3d delta = T_world_base_last_keyframe.inverse() * T_world_base;
    return delta.translation().norm() >= config.keyframe_distance_m ||
           RadToDeg(RotationAngle(delta.linear())) >= config.keyframe_angle_deg;
}

std::vector<WrittenPose> RadarMapper::State::Write(const std::vector<SmoothedPose> &smoothed,
                                                   double &map_update_ms) {
    const auto t_map = Clock::now();
    std::vector<WrittenPose> out;
    bool updated = false;
    for (const SmoothedPose &pose : smoothed) {
        if (pending.empty() || pending.front().written.stamp_ns != pose.stamp_ns)
            throw std::logic_error("RadarMapper: the smoother and the pending scans disagree");
        PendingScan scan = std::move(pending.front());
        pending.pop_front();
        WrittenPose &written = scan.written;
        written.T_world_base = pose.T_world_base;
        written.covariance = pose.motion_covariance;
        if (!scan.in_map && (!scan.fallback || config.update_map_on_fallback) &&
            (map.empty() || IsKeyframe(pose.T_world_base))) {
            written.map_points_added_world =
                map.Update(pose.T_world_base * scan.p_base, pose.T_world_base.translation());
            T_world_base_last_keyframe = pose.T_world_base;
            written.map_updated = true;
            updated = true;
        }
        out.push_back(std::move(written));
    }
    if (updated) map.BuildIndex();  // PCL's float copy of the map is part of the update's cost
    map_update_ms = MillisecondsSince(t_map);
    return out;
}

}  // namespace dorado::mapping
