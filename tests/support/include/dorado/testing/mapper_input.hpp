#pragma once
/// A mapper input of a prior alone: no Doppler, no mask, no ground (what most mapper tests feed).

#include "dorado/mapping/radar_mapper.hpp"

namespace dorado::testing {

inline mapping::MapperInput PriorInput(const mapping::MotionPrior &prior, double dt_s) {
    mapping::MapperInput input;
    input.prior = prior;
    input.dt_s = dt_s;
    return input;
}

}  // namespace dorado::testing
