#pragma once
// Internal: what the front ends' prior step returns (radar_front_end.cpp,
// multi_radar_front_end.cpp).

#include <string>

#include "dorado/frontend/radar_front_end.hpp"

namespace dorado::frontend {

/// The motion prior of one scan, and how it was chosen.
struct BuiltPrior {
    mapping::MotionPrior prior;
    mapping::PriorKind requested = mapping::PriorKind::kDoppler;
    mapping::PriorKind used = mapping::PriorKind::kDoppler;
    bool first_scan = false;  ///< the first scan after a reset: the world's origin
    PriorSubstitution substitution = PriorSubstitution::kNone;
    std::string substitution_detail;
};

}  // namespace dorado::frontend
