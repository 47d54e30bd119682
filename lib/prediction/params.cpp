#include "prediction/params.h"

namespace evade::prediction {

PredictorParams PredictorParams::from_config(const config::Node& s) { return config::load<PredictorParams>(s); }

}  // namespace evade::prediction
