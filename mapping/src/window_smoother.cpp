// The fixed-lag smoother (design and the anchor rule in window_smoother.hpp), alone in its Ceres
// TU.
#include "dorado/mapping/window_smoother.hpp"

#include <ceres/ceres.h>

#include <cmath>
#include <deque>
#include <stdexcept>
#include <string>

#include "cost_functions.hpp"
#include "dorado/core/require.hpp"
#include "robust_loss.hpp"
#include "window_factors.hpp"

namespace dorado::mapping {

namespace {

// One state's parameter blocks and the measurements kept for its factors.
struct Slot {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    Eigen::Vector3d w = Eigen::Vector3d::Zero();
    WindowScan scan;  ///< measurements (its initial values are not used after Add)
    Eigen::Vector3d kinematic_sigmas = Eigen::Vector3d::Ones();
};

}  // namespace

void WindowConfig::Validate() const {
    Require(size >= 1 && size <= 100, "mapper.window.size", "must be in [1, 100]");
    Require((qc_linear.array() > 0.0).all() && qc_linear.allFinite(), "mapper.window.qc_linear",
            "must be > 0");
    Require((qc_angular.array() > 0.0).all() && qc_angular.allFinite(), "mapper.window.qc_angular",
            "must be > 0");
    Require(gyro_sigma_radps > 0.0, "mapper.window.gyro_sigma_radps", "must be > 0");
    Require(gyro_bias_sigma_radps > 0.0, "mapper.window.gyro_bias_sigma_radps", "must be > 0");
    Require(max_iterations >= 1, "mapper.window.max_iterations", "must be >= 1");
}

struct WindowSmoother::Impl {
    WindowConfig config;
    WindowNoise noise;
    Extrinsics extrinsics;
    VehicleGeometry geometry;
    std::deque<Slot> slots;  ///< slots[0] is the anchor (pose fixed), the rest are free
    Eigen::Vector3d bias = Eigen::Vector3d::Zero();
    Eigen::Vector3d bias_prior = Eigen::Vector3d::Zero();

    // The kinematic model's violation sigmas at a twist (as KinematicModel::ModelCovariance).
    Eigen::Vector3d KinematicSigmas(const Eigen::Vector3d &v, const Eigen::Vector3d &w) const {
        const KinematicModelNoise &n = geometry.model_noise;
        const double yaw_rate = std::abs(w.z()), speed = std::abs(v.x());
        const double icr = n.sigma_icr_x_m * yaw_rate;
        const double slip = n.rear_slip_rad_per_mps2 * speed * speed * yaw_rate;
        Eigen::Vector3d sigmas(
            std::sqrt(icr * icr + slip * slip + n.sigma_lateral_mps * n.sigma_lateral_mps),
            n.sigma_vertical_mps, n.sigma_roll_rate_radps);
        return sigmas.cwiseMax(1e-6);  // a zero model_noise is a hard (but finite) constraint
    }

    void Solve();
};

void WindowSmoother::Impl::Solve() {
    ceres::Problem::Options problem_options;
    problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem_options.manifold_ownership = ceres::TAKE_OWNERSHIP;
    ceres::Problem problem(problem_options);
    const auto loss = MakeLoss(noise.loss, noise.loss_scale);
    const Vector6d qc = (Vector6d() << config.qc_linear, config.qc_angular).finished();
    bool uses_gyro = false;
    for (std::size_t k = 0; k < slots.size(); ++k) {
        Slot &s = slots[k];
        double *p = s.p.data(), *q = s.q.coeffs().data(), *v = s.v.data(), *w = s.w.data();
        for (const Correspondence &m : s.scan.matches)
            problem.AddResidualBlock(
                RegistrationError::Create(m.p_base, m.q_world, m.sqrt_information), loss.get(), p,
                q);
        for (const DopplerObservation &d : s.scan.doppler)
            problem.AddResidualBlock(
                new TwistDopplerError(d.d_radar, d.doppler_mps, extrinsics.T_base_radar,
                                      noise.doppler_sigma_mps),
                loss.get(), v, w);
        if (config.use_kinematic_model)
            problem.AddResidualBlock(
                new KinematicError(geometry.half_wheelbase_m, s.kinematic_sigmas), nullptr, v, w);
        if (s.scan.gyro_base_radps) {
            problem.AddResidualBlock(
                new GyroError(*s.scan.gyro_base_radps, config.gyro_sigma_radps), nullptr, w,
                bias.data());
            uses_gyro = true;
        }
        if (k > 0) {
            Slot &r = slots[k - 1];
            problem.AddResidualBlock(new WnoaError(s.scan.dt_s, qc), nullptr, r.p.data(),
                                     r.q.coeffs().data(), r.v.data(), r.w.data(), p, q, v, w);
        }
        // The pose may have no factor at all (the anchor alone); only add its manifold if used.
        if (problem.HasParameterBlock(q))
            problem.SetManifold(q, new ceres::EigenQuaternionManifold);
    }
    // Gauge: the anchor's pose is held (the world, or the map built from it); see the header.
    Slot &anchor = slots.front();
    if (problem.HasParameterBlock(anchor.p.data()))
        problem.SetParameterBlockConstant(anchor.p.data());
    if (problem.HasParameterBlock(anchor.q.coeffs().data()))
        problem.SetParameterBlockConstant(anchor.q.coeffs().data());
    if (uses_gyro)
        problem.AddResidualBlock(new VectorPriorError(bias_prior, config.gyro_bias_sigma_radps),
                                 nullptr, bias.data());
    if (problem.NumResidualBlocks() == 0) return;

    ceres::Solver::Options options;
    options.linear_solver_type =
        ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE) ||
                ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::EIGEN_SPARSE)
            ? ceres::SPARSE_NORMAL_CHOLESKY
            : ceres::DENSE_NORMAL_CHOLESKY;
    options.max_num_iterations = config.max_iterations;
    options.num_threads = 1;
    options.logging_type = ceres::SILENT;
    options.function_tolerance = 1e-6;
    options.parameter_tolerance = 1e-7;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    for (Slot &s : slots) s.q.normalize();
    if (uses_gyro) bias_prior = bias;  // the bias carries over to the next window as its prior
}

WindowSmoother::WindowSmoother(const WindowConfig &config, const WindowNoise &noise,
                               const Extrinsics &extrinsics, const VehicleGeometry &geometry) {
    config.Validate();
    if (!(noise.doppler_sigma_mps > 0.0 && noise.loss_scale > 0.0))
        throw std::invalid_argument("WindowSmoother: doppler_sigma_mps and loss_scale must be > 0");
    impl_ = std::make_unique<Impl>();
    impl_->config = config;
    impl_->noise = noise;
    impl_->extrinsics = extrinsics;
    impl_->geometry = geometry;
}
WindowSmoother::~WindowSmoother() = default;
WindowSmoother::WindowSmoother(WindowSmoother &&) noexcept = default;
WindowSmoother &WindowSmoother::operator=(WindowSmoother &&) noexcept = default;

WindowState WindowSmoother::Add(const WindowScan &scan) {
    Impl &m = *impl_;
    if (!(std::isfinite(scan.dt_s) && scan.dt_s > 0.0) && !m.slots.empty())
        throw std::invalid_argument("WindowSmoother::Add: dt must be finite and > 0");
    Slot slot;
    slot.p = scan.T_world_base_initial.translation();
    slot.q = Eigen::Quaterniond(scan.T_world_base_initial.linear()).normalized();
    slot.v = scan.v_base_initial;
    slot.w = scan.omega_base_initial;
    slot.kinematic_sigmas = m.KinematicSigmas(slot.v, slot.w);
    slot.scan = scan;
    m.slots.push_back(std::move(slot));
    while (static_cast<int>(m.slots.size()) > m.config.size + 1) m.slots.pop_front();
    m.Solve();
    return States().back();
}

std::vector<WindowState> WindowSmoother::States() const {
    std::vector<WindowState> out;
    for (const Slot &s : impl_->slots) {
        WindowState state;
        state.T_world_base.linear() = s.q.toRotationMatrix();
        state.T_world_base.translation() = s.p;
        state.v_base_mps = s.v;
        state.omega_base_radps = s.w;
        out.push_back(state);
    }
    return out;
}

Eigen::Vector3d WindowSmoother::gyro_bias_radps() const {
    return impl_->bias;
}

}  // namespace dorado::mapping
