// The predictor process core: OBSTACLES -> OBSTACLE_PREDICTIONS, one output
// per accepted obstacle list, stamped with that list's utime.
#pragma once

#include <memory>

#include "bus/core.h"
#include "config/config.h"
#include "prediction/predictor.h"

namespace evade::prediction {

inline constexpr const char* kObstaclesChannel = "OBSTACLES";
inline constexpr const char* kPredictionsChannel = "OBSTACLE_PREDICTIONS";

class PredictorCore : public bus::Core {
 public:
  explicit PredictorCore(const PredictorParams& params);
  // The core of the whole configuration (the `predictor:` section);
  // throws ConfigError (file:line: key).
  static std::unique_ptr<PredictorCore> from_config(const config::Node& root);
  const Predictor& predictor() const { return predictor_; }

 private:
  void on_obstacles(const evade::obstacle_list_t& msg);
  Predictor predictor_;
  evade::prediction_list_t out_{};  // reused between frames
};

}  // namespace evade::prediction
