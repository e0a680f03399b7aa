// What each part of the front end runs with (its config on this platform), and the words and keys
// of a prior's substitution.
#include <stdexcept>
#include <string>

#include "dorado/core/angles.hpp"
#include "front_end_state.hpp"

namespace dorado::frontend {

// With the mapper on, the odometry's method follows the prior: the imu+doppler prior needs the
// gyro-rotation chain, every other prior the Doppler model's (gyro-only odometry has no Doppler
// velocity, hence no mask).
// On an unconstrained platform (no Doppler rotation) the priors that do not use the odometry's
// twist (none, constvel, imu) run the gyro chain (kImu) for the mask; the doppler prior is refused.
odometry::DopplerOdometryConfig OdometryConfigFor(const FrontEndConfig &config,
                                                  const VehicleGeometry &geometry) {
    odometry::DopplerOdometryConfig odometry = config.odometry;
    if (config.run_mapper) {
        const bool unconstrained = geometry.model == VehicleModel::kUnconstrained;
        if (unconstrained && config.prior == mapping::PriorKind::kDoppler)
            throw std::invalid_argument(
                "vehicle.model: unconstrained (no kinematic constraint) gives no rotation from the "
                "Doppler: the doppler prior is refused; use --prior imu+doppler (gyro rotation, "
                "Doppler velocity)");
        odometry.method = config.prior == mapping::PriorKind::kImuDoppler
                              ? odometry::OdometryMethod::kImuDoppler
                          : unconstrained ? odometry::OdometryMethod::kImu
                                          : odometry::OdometryMethod::kDoppler;
    }
    return odometry;
}

void FrontEndConfig::Validate() const {
    odometry.Validate();
    if (run_mapper) {
        mapper.Validate();
        prior_noise.Validate();
    }
}

const char *ToString(PriorSubstitution cause) {
    switch (cause) {
        case PriorSubstitution::kNone:
            return "";
        case PriorSubstitution::kNoImuSamples:
            return "no imu samples";
        case PriorSubstitution::kInvalidDopplerVelocity:
            return "doppler: no valid velocity";
        case PriorSubstitution::kDiscontinuousTwist:
            return "doppler: twist discontinuous with the previous one";
        case PriorSubstitution::kAngularRateLimit:
            return "doppler: angular rate above max_angular_rate_radps";
    }
    return "?";
}

SubstitutionCause SubstitutionCauseOf(const FrontEndResult &result) {
    const bool ego = result.prior_substitution == PriorSubstitution::kInvalidDopplerVelocity;
    return {result.prior_substitution,
            ego ? result.odometry.ego.failure : odometry::EgoVelocityFailure::kNone};
}

std::string SubstitutionKey(const SubstitutionCause &cause) {
    if (cause.first == PriorSubstitution::kInvalidDopplerVelocity)
        return std::string("doppler: ") + odometry::ToString(cause.second);
    return ToString(cause.first);
}

// The plane's normal (-a, -b, 1) normalised; its x and y are -sin(pitch) and sin(roll) cos(pitch),
// so to first order their covariance is the fit's roll/pitch covariance turned by 90 degrees.
mapping::GroundUp GroundUpFromFit(const odometry::GroundObservation &fit,
                                  const odometry::GroundAttitudeConfig &ground) {
    mapping::GroundUp up;
    up.up_base = Eigen::Vector3d(-fit.slope.x(), -fit.slope.y(), 1.0).normalized();
    Eigen::Matrix2d M;
    M << 0.0, -1.0, 1.0, 0.0;  // [up_x, up_y] = M [roll, pitch] to first order
    const double slope_rad = DegToRad(ground.road_slope_sigma_deg);
    up.covariance = M * fit.cov_roll_pitch * M.transpose() +
                    slope_rad * slope_rad * Eigen::Matrix2d::Identity();
    up.max_innovation_chi2 = ground.max_innovation_chi2;
    return up;
}

}  // namespace dorado::frontend
