// dorado_ros's parameters on one field list (ros/src/node_fields.hpp, ROS-free): every member of
// NodeSettings is a parameter of the list, or named here as read otherwise.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "dorado/io/field_yaml.hpp"
#include "dorado/testing/field_coverage.hpp"
#include "node_fields.hpp"

namespace dorado::ros_node {
namespace {

TEST(NodeFields, EveryMemberIsAParameter) {
    NodeSettings s;
    // dataset: the `config` YAML; front_end: odometry_config + mapper_config (the list sets
    // some of its members: mapper, prior, method, use_mask, min_points, use_power); needs_imu,
    // T_base_child, description: derived; T_world_child_initial: initial_pose (16 numbers);
    // gaps.report_factor: not a parameter.
    EXPECT_EQ(testing::MembersWithoutField(
                  s, {&s.dataset, &s.front_end, &s.needs_imu, &s.T_base_child, &s.description,
                      &s.T_world_child_initial, &s.gaps.report_factor}),
              std::vector<std::string>{});
}

TEST(NodeFields, EachParameterOnce) {
    std::vector<std::string> names;
    for (const auto &row : io::ListFields(NodeSettings{})) names.push_back(row.key);
    for (std::size_t i = 0; i < names.size(); ++i)
        for (std::size_t j = i + 1; j < names.size(); ++j) EXPECT_NE(names[i], names[j]);
    // The parameters read by hand are not in the list.
    for (const char *own : {"config", "odometry_config", "mapper_config", "threshold_mode",
                            "threshold_value", "initial_pose", "sensor_pose"})
        EXPECT_EQ(std::count(names.begin(), names.end(), own), 0) << own;
}

}  // namespace
}  // namespace dorado::ros_node
