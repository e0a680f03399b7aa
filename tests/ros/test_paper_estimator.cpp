// The paper node's threshold_mode / threshold_value (ros/common/paper_estimator.hpp), without ROS:
// each accepted mode sets dorado's estimator, and any other is an error naming the parameter and
// listing the accepted values (never a silent `fixed`).
#include <gtest/gtest.h>

#include <string>

#include "dorado/io/config_error.hpp"
#include "paper_estimator.hpp"

namespace {

using dorado::odometry::EgoVelocityConfig;
using dorado::odometry::RobustMethod;
using dorado::odometry::TrimMode;
using dorado::ros_node::ApplyPaperThreshold;

TEST(PaperThreshold, RansacTakesTheValueAsTheGateOfStrongReturns) {
    EgoVelocityConfig ego;
    ego.method = RobustMethod::kTrimmedIrls;
    ApplyPaperThreshold(std::string("ransac"), 0.3, ego);
    EXPECT_EQ(ego.method, RobustMethod::kRansac);
    EXPECT_NEAR(ego.doppler_sigma_mps * ego.gate_sigmas, 0.3, 1e-12);
}

TEST(PaperThreshold, TrimModesSelectTrimmedIrlsWithThatMode) {
    for (const auto &[name, mode] :
         {std::pair<const char *, TrimMode>{"percent", TrimMode::kPercent},
          {"mad", TrimMode::kMad},
          {"fixed", TrimMode::kFixed}}) {
        EgoVelocityConfig ego;
        ApplyPaperThreshold(std::string(name), 0.25, ego);
        EXPECT_EQ(ego.method, RobustMethod::kTrimmedIrls) << name;
        EXPECT_EQ(ego.trim_mode, mode) << name;
        EXPECT_EQ(ego.trim_value, 0.25) << name;
    }
}

TEST(PaperThreshold, WithoutAModeTheConfiguredMethodStays) {
    EgoVelocityConfig irls;
    irls.method = RobustMethod::kTrimmedIrls;
    irls.trim_mode = TrimMode::kMad;
    ApplyPaperThreshold(std::nullopt, 0.5, irls);
    EXPECT_EQ(irls.method, RobustMethod::kTrimmedIrls);
    EXPECT_EQ(irls.trim_mode, TrimMode::kMad);
    EgoVelocityConfig ransac;  // RANSAC by default: the value is its gate
    ApplyPaperThreshold(std::nullopt, 0.3, ransac);
    EXPECT_EQ(ransac.method, RobustMethod::kRansac);
    EXPECT_NEAR(ransac.doppler_sigma_mps * ransac.gate_sigmas, 0.3, 1e-12);
}

TEST(PaperThreshold, AnUnknownModeIsAnErrorNamingTheParameterAndTheAcceptedValues) {
    for (const char *bad : {"percentile", "RANSAC", ""}) {
        EgoVelocityConfig ego;
        ego.method = RobustMethod::kRansac;
        try {
            ApplyPaperThreshold(std::string(bad), 0.1, ego);
            ADD_FAILURE() << "threshold_mode '" << bad << "' was accepted";
        } catch (const dorado::io::ConfigError &e) {
            EXPECT_EQ(std::string(e.what()),
                      "parameter 'threshold_mode': unknown threshold_mode '" + std::string(bad) +
                          "' (ransac, percent, mad, fixed)");
        }
        EXPECT_EQ(ego.method, RobustMethod::kRansac);  // untouched
    }
}

}  // namespace
