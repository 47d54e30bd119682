// The predictor process core: OBSTACLES -> OBSTACLE_PREDICTIONS, one output
// per accepted obstacle list, stamped with that list's utime.
#pragma once

#include "bus/core.h"
#include "prediction/predictor.h"

namespace evade::prediction {

inline constexpr const char* kObstaclesChannel = "OBSTACLES";
inline constexpr const char* kPredictionsChannel = "OBSTACLE_PREDICTIONS";

class PredictorCore : public bus::Core {
 public:
  explicit PredictorCore(const PredictorParams& params);
  const Predictor& predictor() const { return predictor_; }

 private:
  void on_obstacles(const evade::obstacle_list_t& msg);
  Predictor predictor_;
  evade::prediction_list_t out_{};  // reused between frames
};

}  // namespace evade::prediction
