// Ceres pose refinement, alone in this TU.
#include <ceres/ceres.h>

#include <Eigen/Eigenvalues>
#include <memory>

#include "cost_functions.hpp"
#include "ground_factor.hpp"
#include "pose_information.hpp"
#include "registration.hpp"
#include "robust_loss.hpp"

namespace dorado::mapping {

namespace {

// A pose as Ceres' parameter blocks: position and unit quaternion (x, y, z, w).
struct PoseBlocks {
    Eigen::Vector3d t;
    Eigen::Quaterniond q;

    explicit PoseBlocks(const Eigen::Isometry3d &T)
        : t(T.translation()), q(Eigen::Quaterniond(T.linear()).normalized()) {}
    [[nodiscard]] Eigen::Isometry3d Pose() const {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.linear() = q.normalized().toRotationMatrix();
        T.translation() = t;
        return T;
    }
    [[nodiscard]] bool Finite() const { return t.allFinite() && q.coeffs().allFinite(); }
};

// Solves a one-pose problem (pose: its parameter blocks, moved to the solution); the iterations it
// took, usable when Ceres' solution is.
struct Solved {
    bool usable = false;
    int iterations = 0;
};

Solved Solve(ceres::Problem &problem, PoseBlocks &pose, const MapperConfig &config) {
    problem.SetManifold(pose.q.coeffs().data(), new ceres::EigenQuaternionManifold);
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;  // 6 unknowns: 6x6 normal equations
    options.max_num_iterations = config.refine_max_iterations;
    options.num_threads = 1;
    options.logging_type = ceres::SILENT;
    options.minimizer_progress_to_stdout = false;
    options.function_tolerance = 1e-6;
    options.parameter_tolerance = 1e-7;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    return {summary.IsSolutionUsable() && pose.Finite(),
            static_cast<int>(summary.iterations.size())};
}

ceres::Problem::Options ProblemOptions() {
    ceres::Problem::Options options;
    options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    options.manifold_ownership = ceres::TAKE_OWNERSHIP;
    return options;
}
// The Doppler residuals of the static points, sharing one velocity of the pose since
// T_world_base_prev.
void AddDoppler(ceres::Problem &problem, const RefinementInput &input,
                const std::vector<DopplerObservation> *doppler,
                const Eigen::Isometry3d &T_world_base_prev, const MapperConfig &config,
                const ceres::LossFunction *loss, PoseBlocks &pose) {
    if (doppler == nullptr || doppler->empty()) return;
    const auto velocity =
        std::make_shared<SharedRadarVelocity>(input.T_base_radar, T_world_base_prev, input.dt_s);
    for (const auto &d : *doppler)
        problem.AddResidualBlock(
            new DopplerError(d.d_radar, d.doppler_mps, velocity, config.doppler_sigma_mps),
            const_cast<ceres::LossFunction *>(loss), pose.t.data(), pose.q.coeffs().data());
}

// The registration's residuals: each match on its map point's local distribution.
void AddRegistration(ceres::Problem &problem, const RefinementInput &input,
                     const ceres::LossFunction *loss, PoseBlocks &pose) {
    for (const auto &m : *input.matches)
        problem.AddResidualBlock(RegistrationError::Create(m.p_base, m.q_world, m.sqrt_information),
                                 const_cast<ceres::LossFunction *>(loss), pose.t.data(),
                                 pose.q.coeffs().data());
}

// The ground's residual on the pose's absolute roll and pitch, when the observation is consistent
// with the step's prior (its rotation covariance; a ridge or a kerb under the vehicle tilts the
// fitted plane beyond it) and robust like the registration's. True when it was added.
bool AddGround(ceres::Problem &problem, const GroundUp *ground, const MotionPrior &prior,
               const ceres::LossFunction *loss, PoseBlocks &pose) {
    if (ground == nullptr) return false;
    if (!GroundConsistent(*ground, prior.T_world_base, prior.covariance.bottomRightCorner<3, 3>()))
        return false;
    problem.AddResidualBlock(GroundUpError::Create(*ground),
                             const_cast<ceres::LossFunction *>(loss), pose.q.coeffs().data());
    return true;
}

}  // namespace

namespace {

// What step 1 found: the registered pose, when usable.
struct JointRegistration {
    Eigen::Isometry3d T_map_base = Eigen::Isometry3d::Identity();
    bool usable = false;
    int iterations = 0;
    bool ground_used = false;
};

// Registration + Doppler + prior residuals, from input's initial pose.
JointRegistration RegisterJointly(const RefinementInput &input, const MapperConfig &config,
                                  const ceres::LossFunction *loss) {
    PoseBlocks pose(input.T_world_base_initial);
    ceres::Problem problem(ProblemOptions());
    AddRegistration(problem, input, loss, pose);
    AddDoppler(problem, input, input.doppler, input.T_world_base_prev, config, loss, pose);
    problem.AddResidualBlock(PriorError::Create(input.prior->T_world_base,
                                                InverseCholeskyFactor<6>(input.prior->covariance)),
                             nullptr, pose.t.data(), pose.q.coeffs().data());
    JointRegistration out;
    out.ground_used = AddGround(problem, input.ground, *input.prior, loss, pose);
    const Solved solved = Solve(problem, pose, config);
    out.usable = solved.usable;
    out.iterations = solved.iterations;
    out.T_map_base = pose.Pose();
    return out;
}

}  // namespace

RefinementOutput RefinePose(const RefinementInput &input, const MapperConfig &config) {
    RefinementOutput out;
    out.T_world_base = input.T_world_base_initial;
    const auto loss = MakeLoss(config.kernel, config.kernel_scale);
    const JointRegistration joint = RegisterJointly(input, config, loss.get());
    out.iterations = joint.iterations;
    out.ground_used = joint.ground_used;
    if (!joint.usable) return out;
    out.registered = RegistrationCovariance(joint.T_map_base, *input.matches, loss.get(), config);
    if (!out.registered.valid) return out;
    if (out.registered.weak_directions > 0) {
        // Solution remapping (Zhang et al. 2016): along the weak directions the registered pose
        // keeps the prior's value; the correction from the prior is kept across the strong ones.
        const Eigen::Isometry3d &T_world_base_prior = input.prior->T_world_base;
        const Vector6d xi = LogSE3(T_world_base_prior.inverse() * out.registered.T_world_base);
        out.registered.T_world_base =
            T_world_base_prior * ExpSE3(out.registered.strong_projector * xi);
    }
    out.T_world_base = out.registered.T_world_base;
    out.usable = true;
    return out;
}

}  // namespace dorado::mapping
