// Ceres pose refinement, alone in this TU.
#include <ceres/ceres.h>

#include <memory>

#include "cost_functions.hpp"
#include "registration.hpp"

namespace dorado::mapping {

namespace {

std::unique_ptr<ceres::LossFunction> MakeLoss(RobustKernel kernel, double scale) {
    switch (kernel) {
        case RobustKernel::kNone:
            return nullptr;
        case RobustKernel::kHuber:
            return std::make_unique<ceres::HuberLoss>(scale);
        case RobustKernel::kCauchy:
            return std::make_unique<ceres::CauchyLoss>(scale);
        case RobustKernel::kTukey:
            return std::make_unique<ceres::TukeyLoss>(scale);
    }
    return nullptr;
}

}  // namespace

RefinementOutput RefinePose(const RefinementInput &input, const MapperConfig &config) {
    Eigen::Vector3d t_world_base = input.T_world_base_initial.translation();
    Eigen::Quaterniond q_world_base(input.T_world_base_initial.linear());
    q_world_base.normalize();

    ceres::Problem::Options problem_options;
    problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem_options.manifold_ownership = ceres::TAKE_OWNERSHIP;
    ceres::Problem problem(problem_options);
    const auto registration_loss = MakeLoss(config.kernel, config.kernel_scale);
    const auto doppler_loss = MakeLoss(config.kernel, config.kernel_scale);

    for (const auto &m : *input.matches) {
        problem.AddResidualBlock(RegistrationError::Create(m.p_base, m.q_world, m.sqrt_information),
                                 registration_loss.get(), t_world_base.data(),
                                 q_world_base.coeffs().data());
    }
    if (input.doppler != nullptr && !input.doppler->empty()) {
        const auto velocity = std::make_shared<SharedRadarVelocity>(
            input.T_base_radar, input.T_world_base_prev, input.dt_s);
        for (const auto &d : *input.doppler) {
            problem.AddResidualBlock(
                new DopplerError(d.d_radar, d.doppler_mps, velocity, config.doppler_sigma_mps),
                doppler_loss.get(), t_world_base.data(), q_world_base.coeffs().data());
        }
    }
    // The prior is trusted as Gaussian: no robust loss, its covariance already says how much.
    problem.AddResidualBlock(PriorError::Create(input.prior->T_world_base,
                                                InverseCholeskyFactor<6>(input.prior->covariance)),
                             nullptr, t_world_base.data(), q_world_base.coeffs().data());
    // Only the new pose is free: the map and the previous pose are fixed, so there is no gauge
    // freedom to remove (unlike pose_graph_3d, which pins its first pose).
    problem.SetManifold(q_world_base.coeffs().data(), new ceres::EigenQuaternionManifold);

    ceres::Solver::Options options;
    options.linear_solver_type =
        ceres::DENSE_NORMAL_CHOLESKY;  // 6 unknowns: the 6x6 normal equations
    options.max_num_iterations = config.refine_max_iterations;
    options.num_threads = 1;
    options.logging_type = ceres::SILENT;
    options.minimizer_progress_to_stdout = false;
    options.function_tolerance = 1e-6;
    options.parameter_tolerance = 1e-7;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);

    RefinementOutput out;
    out.iterations = static_cast<int>(summary.iterations.size());
    out.usable =
        summary.IsSolutionUsable() && t_world_base.allFinite() && q_world_base.coeffs().allFinite();
    out.T_world_base = Eigen::Isometry3d::Identity();
    out.T_world_base.linear() = q_world_base.normalized().toRotationMatrix();
    out.T_world_base.translation() = t_world_base;
    if (!out.usable) out.T_world_base = input.T_world_base_initial;
    return out;
}

}  // namespace dorado::mapping
