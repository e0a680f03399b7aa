#pragma once
/// @file window_smoother.hpp
/// A fixed-lag smoother over the last K scans (`refinement: window`): a pose and a body
/// twist per scan (and one gyro bias when gyro rates are given), estimated jointly by Ceres from
/// scan-to-map registration residuals, Doppler residuals of the static points, a
/// white-noise-on-acceleration motion prior between consecutive states (as steam_icp), the paper's
/// kinematic model (eq. 3-4) as a soft factor and gyro factors.
///
/// How the oldest state leaves the window: it is FIXED, not marginalised. The window holds K free
/// states plus one anchor before them whose pose is held constant (its twist stays free, with its
/// own Doppler and kinematic factors); when a state becomes older than the anchor it is dropped
/// with its factors. Why: the local map the registration residuals match against was built from
/// those same older poses and is itself held fixed, so the past is already conditioned on; a Schur
/// marginal of the old poses would count the scans that made the map a second time. What fixing
/// loses is the marginal information of the dropped twists (the WNOA link to the anchor's twist
/// only). Ceres headers stay in window_smoother.cpp.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <vector>

#include "dorado/core/extrinsics.hpp"
#include "dorado/mapping/measurements.hpp"

namespace dorado::mapping {

/// Settings of the window smoother; every default is explained in configs/mapper.yaml
/// (mapper.window).
struct WindowConfig {
    int size = 2;  ///< K, the free states (scans) in the window
    /// White-noise-on-acceleration power spectral densities (Qc diagonal) of the body's linear
    /// [m^2/s^3] and angular [rad^2/s^3] acceleration, per base axis (x forward, y left, z up).
    Eigen::Vector3d qc_linear{0.01, 0.001, 0.001};
    Eigen::Vector3d qc_angular{0.0001, 0.0001, 0.001};
    bool use_kinematic_model =
        true;                        ///< the paper's eq. 3-4 as a soft factor (vehicle.model_noise)
    double gyro_sigma_radps = 0.01;  ///< per-scan mean gyro rate noise
    double gyro_bias_sigma_radps = 0.01;  ///< prior on the gyro bias (and on its change per solve)
    int max_iterations = 5;

    /// Throws std::invalid_argument naming the first bad key (window.*).
    void Validate() const;
};

/// Everything the smoother keeps about one scan.
struct WindowScan {
    double dt_s = kFirstScanIntervalS;  ///< since the previous scan (ignored for the first)
    Eigen::Isometry3d T_world_base_initial = Eigen::Isometry3d::Identity();
    Eigen::Vector3d v_base_initial = Eigen::Vector3d::Zero();
    Eigen::Vector3d omega_base_initial = Eigen::Vector3d::Zero();
    std::vector<Correspondence> matches;  ///< empty: no registration (first scan, fallback)
    std::vector<DopplerObservation> doppler;
    std::optional<Eigen::Vector3d> gyro_base_radps;  ///< mean gyro rate, base frame
};

/// The measurement noise and robust loss the smoother shares with the mapper (the mapper passes
/// its doppler_sigma_mps, kernel and kernel_scale).
struct WindowNoise {
    double doppler_sigma_mps = 0.0;
    RobustKernel loss = RobustKernel::kNone;
    double loss_scale = 1.0;
};

/// The smoothed estimate of one state.
struct WindowState {
    Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
    Eigen::Vector3d v_base_mps = Eigen::Vector3d::Zero();
    Eigen::Vector3d omega_base_radps = Eigen::Vector3d::Zero();
};

class WindowSmoother {
  public:
    /// The first scan ever added is the world anchor: its pose is held at its initial value.
    WindowSmoother(const WindowConfig &config, const WindowNoise &noise,
                   const Extrinsics &extrinsics, const VehicleGeometry &geometry);
    ~WindowSmoother();
    WindowSmoother(WindowSmoother &&) noexcept;
    WindowSmoother &operator=(WindowSmoother &&) noexcept;

    /// Adds a scan, slides the window and solves; returns the newest state's estimate.
    WindowState Add(const WindowScan &scan);

    /// The current estimates, oldest (the anchor) first.
    [[nodiscard]] std::vector<WindowState> States() const;
    [[nodiscard]] Eigen::Vector3d gyro_bias_radps() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace dorado::mapping
