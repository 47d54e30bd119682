#include "prediction/predictor_core.h"

namespace evade::prediction {

PredictorCore::PredictorCore(const PredictorParams& params) : bus::Core("predictor"), predictor_(params) {
  subscribe<evade::obstacle_list_t>(kObstaclesChannel, [this](const evade::obstacle_list_t& m) { on_obstacles(m); });
  if (params.occluded.enabled)
    subscribe<evade::hidden_region_list_t>(
        "OCCLUSIONS", [this](const evade::hidden_region_list_t& m) { predictor_.set_hidden_regions(m); });
}

void PredictorCore::on_obstacles(const evade::obstacle_list_t& msg) {
  FrameStats st;
  if (!predictor_.process(msg, &out_, &st)) {
    count("stale_frames");  // utime not after the previous frame: skipped
    return;
  }
  count("frames");
  if (st.created) count("tracks_created", st.created);
  if (st.dropped) count("tracks_dropped", st.dropped);
  if (st.coasting) count("track_frames_coasted", st.coasting);
  if (st.hidden) count("track_frames_hidden", st.hidden);
  if (st.malformed) count("malformed_obstacles", st.malformed);
  if (st.gap_reset) count("frame_gap_resets");
  if (st.diverged) count("diverged_tracks");
  publish(kPredictionsChannel, out_);
}

std::unique_ptr<PredictorCore> PredictorCore::from_config(const config::Node& root) {
  return std::make_unique<PredictorCore>(PredictorParams::from_config(root.section("predictor")));
}

}  // namespace evade::prediction
