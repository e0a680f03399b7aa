// dorado_ros's parameters on one field list (ros/common/node_fields.hpp, ROS-free): every member of
// NodeSettings is a parameter of the list, or named here as read otherwise.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>
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
    // gaps.report_factor: not a parameter; loop_closure: mapper_config's loop_closure section.
    EXPECT_EQ(testing::MembersWithoutField(
                  s, {&s.dataset, &s.front_end, &s.loop_closure, &s.needs_imu, &s.T_base_child,
                      &s.description, &s.T_world_child_initial, &s.gaps.report_factor}),
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

// docs/live_node.md's parameter table is written by hand (it explains the parameters read by hand
// too): every parameter of the list and every one read by hand has a row naming it.
TEST(NodeFields, TheDocsTableNamesEveryParameter) {
    std::ifstream file(DORADO_SOURCE_DIR "/docs/live_node.md");
    std::stringstream text;
    text << file.rdbuf();
    std::vector<std::string> rows;  // the table's first cells
    std::string line;
    std::istringstream lines(text.str());
    bool in_table = false;
    while (std::getline(lines, line)) {
        if (line.rfind("| parameter |", 0) == 0)
            in_table = true;
        else if (in_table && line.rfind("|", 0) != 0)
            break;
        else if (in_table)
            rows.push_back(line.substr(0, line.find('|', 1)));
    }
    ASSERT_FALSE(rows.empty()) << "docs/live_node.md has no '| parameter |' table";
    const auto named = [&](const std::string &name) {
        return std::any_of(rows.begin(), rows.end(), [&](const std::string &cell) {
            return cell.find('`' + name + '`') != std::string::npos;
        });
    };
    for (const std::string &name : ParameterNames())  // the list's and those read by hand
        EXPECT_TRUE(named(name)) << "docs/live_node.md's parameter table lacks `" << name << "`";
}

}  // namespace
}  // namespace dorado::ros_node
