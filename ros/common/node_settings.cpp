#include "node_settings.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "dorado/config/map_config.hpp"
#include "dorado/config/odometry_config.hpp"
#include "dorado/core/paper_mount.hpp"
#include "node_fields.hpp"
#include "paper_estimator.hpp"

namespace dorado::ros_node {
namespace {

// The parameters through a ParamSource, with the checks every parameter shares.
class Params {
  public:
    explicit Params(const ParamSource &source) : source_(source) {}

    template <typename T>
    bool Get(const std::string &name, T &value) const {
        return source_.Get(name, value);
    }

    // A list of numbers (ints or doubles) of the given size.
    bool GetNumbers(const std::string &name, std::size_t size, std::vector<double> &values) const {
        if (!source_.GetNumbers(name, values)) return false;
        if (values.size() != size)
            Fail(name, "must be a list of " + std::to_string(size) + " numbers");
        return true;
    }

    [[noreturn]] void Fail(const std::string &name, const std::string &what) const {
        throw io::ConfigError("parameter '" + name + "': " + what);
    }

  private:
    const ParamSource &source_;
};

// Reads the node's field list (node_fields.hpp): each parameter that is set into its member.
struct ParamFields {
    const Params &params;

    template <typename T>
    void operator()(const char *name, T &member, const char * /*doc*/) const {
        params.Get(name, member);
    }
    template <typename E>
    void operator()(const char *name, E &member, const Choices<E> &names,
                    const char * /*doc*/) const {
        std::string text;
        if (!params.Get(name, text)) return;
        try {
            member = ParseChoice(names, text, name);
        } catch (const std::invalid_argument &e) {
            params.Fail(name, e.what());
        }
    }
};

Eigen::Quaterniond QuaternionXyzw(const std::vector<double> &v, std::size_t first) {
    return Eigen::Quaterniond(v[first + 3], v[first], v[first + 1], v[first + 2]);
}

// The mount: the `config` YAML's, or the paper's launch values; any of the paper's three
// parameters replaces it by MountFromPaperParameters (the others at the launch values).
void ReadMount(const Params &params, bool has_config, NodeSettings &s) {
    PaperMountParameters paper;
    std::vector<double> values;
    bool given = false;
    if (params.GetNumbers("sensor_pose", 7, values)) {
        paper.sensor_position_m = Eigen::Vector3d(values[0], values[1], values[2]);
        paper.sensor_rotation = QuaternionXyzw(values, 3);
        given = true;
    }
    if (params.GetNumbers("calib_rot", 4, values)) {
        paper.calib_rotation = QuaternionXyzw(values, 0);
        given = true;
    }
    given |= params.Get("sensor_to_icr_x", paper.sensor_to_icr_x_m);
    for (const auto *q : {&paper.sensor_rotation, &paper.calib_rotation}) {
        if (!(std::abs(q->norm() - 1.0) < 1e-3))
            params.Fail(q == &paper.sensor_rotation ? "sensor_pose" : "calib_rot",
                        "the quaternion must have norm 1");
    }
    if (has_config && !given) return;  // the dataset YAML's extrinsics
    const PaperMount mount = MountFromPaperParameters(paper);
    s.dataset.extrinsics.T_base_radar = mount.extrinsics.T_base_radar;
    s.dataset.vehicle.half_wheelbase_m = mount.half_wheelbase_m;
    s.T_base_child = mount.T_base_baselink;
}

// The files the parameters override: odometry_config, mapper_config (the mapper off unless
// `mapper`).
void ReadFrontEndFiles(const Params &params, NodeSettings &s) {
    std::string path;
    if (params.Get("odometry_config", path) && !path.empty())
        s.front_end.odometry = config::LoadOdometryConfig(path);
    config::MapCommandConfig map_config;
    if (params.Get("mapper_config", path) && !path.empty())
        map_config = config::LoadMapConfig(path);
    s.front_end.mapper = map_config.mapper;
    s.front_end.prior_noise = map_config.prior;
    s.loop_closure = map_config.loop_closure;
    s.front_end.run_mapper = false;
}

// The paper's estimator keys on dorado's ego-velocity settings (paper_estimator.hpp).
void ReadThreshold(const Params &params, odometry::EgoVelocityConfig &ego) {
    std::string mode;
    double value = 0.0;
    const bool has_mode = params.Get("threshold_mode", mode);
    const bool has_value = params.Get("threshold_value", value);
    ApplyPaperThreshold(has_mode ? std::optional<std::string>(mode) : std::nullopt,
                        has_value ? std::optional<double>(value) : std::nullopt, ego);
}

// The names of the field list's parameters.
struct FieldNames {
    std::vector<std::string> &names;

    template <typename T>
    void operator()(const char *name, T &, const char *) const {
        names.emplace_back(name);
    }
    template <typename E>
    void operator()(const char *name, E &, const Choices<E> &, const char *) const {
        names.emplace_back(name);
    }
};

}  // namespace

std::vector<std::string> ParameterNames() {
    // Read by hand (node_fields.hpp says which), then the field list.
    std::vector<std::string> names{"config",         "odometry_config", "mapper_config",
                                   "sensor_pose",    "calib_rot",       "sensor_to_icr_x",
                                   "threshold_mode", "threshold_value", "initial_pose"};
    NodeSettings s;
    VisitFields(s, FieldNames{names});
    return names;
}

NodeSettings ReadNodeSettings(const ParamSource &source) {
    const Params params(source);
    NodeSettings s;
    std::string config_path;
    const bool has_config = params.Get("config", config_path) && !config_path.empty();
    if (has_config) s.dataset = io::LoadDatasetConfig(config_path);
    s.description = has_config ? "dataset " + config_path : "the paper's Hugin defaults";
    ReadMount(params, has_config, s);
    ReadFrontEndFiles(params, s);
    s.input_topic = s.dataset.rosbag.radar_topic;
    s.imu_topic = s.dataset.rosbag.imu_topic;
    VisitFields(s, ParamFields{params});
    ReadThreshold(params, s.front_end.odometry.ego_velocity);
    s.front_end.odometry.ego_velocity.sensor = s.dataset.radar;  // the radar: noise, ambiguity
    s.needs_imu = s.front_end.run_mapper ? mapping::NeedsImu(s.front_end.prior)
                                         : odometry::NeedsImu(s.front_end.odometry.method);
    if (s.queue_size < 1) params.Fail("queue_size", "must be >= 1");
    if (!(s.gaps.max_gap_s > 0.0)) params.Fail("max_gap_s", "must be > 0");
    s.local_map_period_s = std::max(1.0, s.local_map_period_s);
    if (s.needs_imu && s.imu_topic.empty())
        params.Fail("imu_topic", "is required: the prior or method needs the IMU");
    if (s.map_frame == s.tf_from_frame || s.map_frame == s.tf_to_frame)
        params.Fail("map_frame", "must differ from tf_from_frame and tf_to_frame (REP 105)");
    std::vector<double> pose;
    if (params.GetNumbers("initial_pose", 16, pose)) {
        const Eigen::Matrix4d M = Eigen::Map<const Eigen::Matrix4d>(pose.data());  // column-major
        if (!M.allFinite() || (M.topLeftCorner<3, 3>().transpose() * M.topLeftCorner<3, 3>() -
                               Eigen::Matrix3d::Identity())
                                      .norm() > 1e-3)
            params.Fail("initial_pose", "must be a rigid transform (16 values, column-major)");
        s.T_world_child_initial.matrix() = M;
    }
    try {
        s.front_end.Validate();
    } catch (const std::invalid_argument &e) {
        throw io::ConfigError(std::string("parameters: ") + e.what());
    }
    return s;
}

}  // namespace dorado::ros_node
