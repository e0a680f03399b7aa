#include "dorado/core/paper_mount.hpp"

namespace dorado {

PaperMount MountFromPaperParameters(const PaperMountParameters &parameters) {
    PaperMount mount;
    const double s_x = -parameters.sensor_to_icr_x_m;
    const Eigen::Quaterniond q_base_radar =
        (parameters.calib_rotation.normalized() * parameters.sensor_rotation.normalized())
            .normalized();
    Eigen::Isometry3d &T_base_radar = mount.extrinsics.T_base_radar;
    T_base_radar.setIdentity();
    T_base_radar.linear() = q_base_radar.toRotationMatrix();
    T_base_radar.translation() << s_x, parameters.sensor_position_m.y(),
        parameters.sensor_position_m.z();
    mount.half_wheelbase_m = 0.0;
    mount.T_base_baselink.setIdentity();
    mount.T_base_baselink.translation().x() = s_x - parameters.sensor_position_m.x();
    return mount;
}

}  // namespace dorado
