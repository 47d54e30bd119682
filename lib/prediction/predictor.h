// OBSTACLES -> OBSTACLE_PREDICTIONS without any bus: one TrackFilter per
// track id, updated at the frame's utime, then rolled forward over the
// planner's horizon with uncertainty-inflated ellipses.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <unordered_map>
#include <vector>

#include "evade/obstacle_list_t.hpp"
#include "evade/prediction_list_t.hpp"
#include "prediction/params.h"
#include "prediction/track_filter.h"

namespace evade::prediction {

struct FrameStats {
  int created = 0;         // new track ids
  int dropped = 0;         // ids unseen for longer than coast_max_s (or whose coasting filter diverged)
  int coasting = 0;        // ids missing from this list, predicted from their filter alone
  int hidden = 0;          // ...of which held where last seen inside a hidden region (occluded.h)
  int updated = 0;         // existing tracks updated
  int malformed = 0;       // obstacles skipped (non-finite, out of range, bad axes, duplicate id)
  int diverged = 0;        // tracks whose filter went non-finite: restarted from the measurement
  bool gap_reset = false;  // frame gap above max_frame_gap_s: all tracks restarted
};

class Predictor {
 public:
  explicit Predictor(const PredictorParams& params);

  // Processes one obstacle list. Returns false (and leaves *out alone) when the
  // frame is not newer than the last one accepted (duplicate or out of order).
  bool process(const evade::obstacle_list_t& in, evade::prediction_list_t* out, FrameStats* stats);

  // Rolls one filtered track forward: index 0 = the filter's current estimate.
  void predict_track(int64_t id, const TrackFilter& filter, evade::track_prediction_t* out) const;

  // The newest OCCLUSIONS: a track missing inside one of its regions is
  // kept as hidden (occluded.h).
  void set_hidden_regions(const evade::hidden_region_list_t& m) { hidden_regions_ = m; }

  const TrackFilter* track(int64_t id) const;
  size_t num_tracks() const { return tracks_.size(); }
  const PredictorParams& params() const { return *params_; }

 private:
  // Shared and immutable: every TrackFilter points at it, so it must not move
  // when the Predictor does.
  std::shared_ptr<const PredictorParams> params_;
  double chi2_position_ = 0;  // chi-square quantile, 2 dof, at the confidence level
  double z_shape_ = 0;        // two-sided normal quantile at the confidence level
  std::unordered_map<int64_t, TrackFilter> tracks_;
  std::unordered_map<int64_t, int64_t> seen_;             // scratch: ids of the current frame
  std::unordered_map<int64_t, int64_t> last_seen_utime_;  // per track: utime of its last measurement
  std::vector<int64_t> coasting_;                         // scratch: ids coasting in the current frame
  std::vector<int64_t> order_;                            // scratch: ids seen in the current frame, in input order
  std::vector<int64_t> created_;                          // scratch: ids new in the current frame
  std::optional<evade::hidden_region_list_t> hidden_regions_;
  std::unordered_map<int64_t, Measurement> last_z_;  // per track: its last measurement
  std::unordered_map<int64_t, double> hidden_;       // scratch: hidden ids of the current frame -> seconds unseen
  // Whether a track missing at utime is kept as hidden (occluded.h).
  bool hidden_at(int64_t id, int64_t utime) const;

  // One frame: measurement updates of the listed tracks (order_, created_),
  // coasting or dropping of the missing ones (coasting_).
  void update_seen(const evade::obstacle_list_t& in, double dt, FrameStats* stats);
  void coast_missing(int64_t utime, double dt, FrameStats* stats);
  int64_t last_utime_ = -1;
};

}  // namespace evade::prediction
