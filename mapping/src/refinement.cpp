// Ceres pose refinement, alone in this TU.
#include <ceres/ceres.h>

#include <Eigen/Eigenvalues>
#include <memory>

#include "cost_functions.hpp"
#include "dorado/mapping/noise_calibration.hpp"
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

RefinementOutput RegisterAlone(const RefinementInput &input, const MapperConfig &config) {
    RefinementOutput out;
    out.T_world_base = input.T_world_base_initial;
    const auto loss = MakeLoss(config.kernel, config.kernel_scale);
    // Only the new pose is free and the map is fixed: no gauge freedom to remove (unlike
    // pose_graph_3d, which pins its first pose).
    PoseBlocks pose(input.T_world_base_initial);
    ceres::Problem problem(ProblemOptions());
    AddRegistration(problem, input, loss.get(), pose);
    const Solved solved = Solve(problem, pose, config);
    out.iterations += solved.iterations;
    if (!solved.usable) return out;
    out.registered = RegistrationCovariance(pose.Pose(), *input.matches, loss.get(), config);
    out.usable = out.registered.valid;
    return out;
}

namespace {

// What step 1 found: the registered pose, when usable.
struct JointRegistration {
    Eigen::Isometry3d T_map_base = Eigen::Isometry3d::Identity();
    bool usable = false;
    int iterations = 0;
    bool ground_used = false;
};

// Step 1: registration + Doppler + prior residuals on the map's chain (the refinement of the
// previous releases, whose registered poses keep the map consistent), from input's initial pose.
JointRegistration RegisterJointly(const RefinementInput &input, const MapperConfig &config,
                                  const ceres::LossFunction *loss) {
    PoseBlocks pose(input.T_world_base_initial);
    ceres::Problem problem(ProblemOptions());
    AddRegistration(problem, input, loss, pose);
    AddDoppler(problem, input, input.doppler_registration, input.T_world_base_prev, config, loss,
               pose);
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

// W with W^T W = the registration's information: its covariance's inverse Cholesky factor, or,
// with weak directions (a singular information), from the eigen-decomposition.
Matrix6d RegistrationSqrtInformation(const RegisteredPose &registered) {
    if (registered.weak_directions == 0) return InverseCholeskyFactor<6>(registered.covariance);
    const Eigen::SelfAdjointEigenSolver<Matrix6d> eig(registered.information);
    const Vector6d sqrt_eigenvalues = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt();
    return sqrt_eigenvalues.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace

RefinementOutput RefinePose(const RefinementInput &input, const MapperConfig &config) {
    RefinementOutput out;
    out.T_world_base = input.T_world_base_initial;
    const auto loss = MakeLoss(config.kernel, config.kernel_scale);
    // 1. The registered pose and its covariance.
    const JointRegistration joint = RegisterJointly(input, config, loss.get());
    out.iterations += joint.iterations;
    out.ground_used = joint.ground_used;
    if (!joint.usable) return out;
    out.registered = RegistrationCovariance(joint.T_map_base, *input.matches, loss.get(), config);
    if (!out.registered.valid) return out;
    if (input.registration_scale != Eigen::Vector2d::Ones()) {  // the online noise calibration
        out.registered.covariance =
            ScaleBlocks(out.registered.covariance, input.registration_scale);
        out.registered.information =
            ScaleBlocks(out.registered.information, input.registration_scale.cwiseInverse());
    }
    if (out.registered.weak_directions > 0) {
        // Solution remapping (Zhang et al. 2016): along the weak directions the registered pose
        // keeps the prior's value; the correction from the prior is kept across the strong ones.
        const Eigen::Isometry3d &T_world_base_prior = input.prior->T_world_base;
        const Vector6d xi = LogSE3(T_world_base_prior.inverse() * out.registered.T_world_base);
        out.registered.T_world_base =
            T_world_base_prior * ExpSE3(out.registered.strong_projector * xi);
    }

    // 2. The output: its prior (a Gaussian: no robust loss) fused with the registered pose as one
    //    6-DoF measurement, so that the registration's hundreds of residuals count only as much as
    //    they show, and the Doppler residuals (none when the prior carries them).
    const MotionPrior &prior = *input.prior_output;
    PoseBlocks pose(prior.T_world_base);
    ceres::Problem problem(ProblemOptions());
    problem.AddResidualBlock(
        PriorError::Create(prior.T_world_base, InverseCholeskyFactor<6>(prior.covariance)), nullptr,
        pose.t.data(), pose.q.coeffs().data());
    problem.AddResidualBlock(PriorError::Create(out.registered.T_world_base,
                                                RegistrationSqrtInformation(out.registered)),
                             nullptr, pose.t.data(), pose.q.coeffs().data());
    AddDoppler(problem, input, input.doppler, input.T_world_base_prev_output, config, loss.get(),
               pose);
    // The ground again on the output's chain (its own estimate of the same scan: once per chain).
    // Its information is not added to the covariance below, which is this scan's motion's
    // relative to the map and the previous pose, not the absolute attitude's.
    out.ground_used = AddGround(problem, input.ground, prior, loss.get(), pose) || out.ground_used;
    const Solved solved = Solve(problem, pose, config);
    out.iterations += solved.iterations;
    if (!solved.usable) return out;
    out.usable = true;
    out.T_world_base = pose.Pose();
    // The output's covariance: the inputs' informations summed (first order at the solution).
    Matrix6d information =
        CovarianceFromInformation(prior.covariance) +
        (out.registered.weak_directions > 0 ? out.registered.information
                                            : CovarianceFromInformation(out.registered.covariance));
    if (input.doppler != nullptr)
        information +=
            DopplerInformation(out.T_world_base, *input.doppler, input.T_world_base_prev_output,
                               input.T_base_radar, input.dt_s, loss.get(), config);
    out.covariance = CovarianceFromInformation(information);
    return out;
}

}  // namespace dorado::mapping
