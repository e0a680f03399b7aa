#include "paper_estimator.hpp"

#include <stdexcept>

#include "dorado/core/config_fields.hpp"
#include "dorado/io/config_error.hpp"
#include "dorado/odometry/odometry_fields.hpp"

namespace dorado::ros_node {
namespace {

// threshold_mode's spellings: "ransac" (no trim mode), then the trimmed_irls trim modes as the
// odometry config spells them (one list: a new trim mode is accepted here too).
Choices<std::optional<odometry::TrimMode>> ThresholdModeChoices() {
    Choices<std::optional<odometry::TrimMode>> choices{{"ransac", std::nullopt}};
    for (const auto &[name, mode] : odometry::TrimModeChoices()) choices.emplace_back(name, mode);
    return choices;
}

}  // namespace

void ApplyPaperThreshold(const std::optional<std::string> &mode, const std::optional<double> &value,
                         odometry::EgoVelocityConfig &ego) {
    std::optional<odometry::TrimMode> trim;
    if (mode) {
        try {
            trim = ParseChoice(ThresholdModeChoices(), *mode, "threshold_mode");
        } catch (const std::invalid_argument &e) {
            throw io::ConfigError(std::string("parameter 'threshold_mode': ") + e.what());
        }
    } else if (ego.method != odometry::RobustMethod::kRansac) {
        return;  // the odometry config's trimmed_irls or none, as it is
    }
    if (!trim) {
        ego.method = odometry::RobustMethod::kRansac;
        // The paper's RANSAC inlier threshold [m/s] is dorado's gate for strong returns.
        if (value) ego.doppler_sigma_mps = *value / ego.gate_sigmas;
        return;
    }
    ego.method = odometry::RobustMethod::kTrimmedIrls;
    ego.trim_mode = *trim;
    if (value) ego.trim_value = *value;
}

}  // namespace dorado::ros_node
