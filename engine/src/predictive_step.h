// Private: the predictive mode's state (being written).
#pragma once

namespace rattle::detail {

struct PredictiveState {};

}  // namespace rattle::detail
