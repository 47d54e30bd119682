// CLEAR MOT (Bernardin & Stiefelhagen, "Evaluating Multiple Object Tracking
// Performance: The CLEAR MOT Metrics", 2008) over a sequence of frames.
//
// Each frame lists the true objects and the tracker's hypotheses. A true
// object is *scored* (it counts in the statistics) or not (out of range,
// not visible, or too large to be one object: a wall). Matching, per frame:
// 1. a true object keeps last frame's hypothesis when that is still within
//    `gate_m`;
// 2. the remaining pairs within the gate are matched nearest first (greedy
//    on the distance, ties by object then hypothesis id: deterministic; it
//    is the optimal assignment whenever gated pairs do not compete).
// The distance is the hypothesis centre's distance to the object's shape
// (0 inside): a tracker sees a car's near side, not its centre. MOTP is the
// centre-to-centre error of the scored matches.
// Counting: a scored object unmatched is a miss; a hypothesis matched to a
// scored object is a true positive (an identity switch when the object's
// previous hypothesis, in any earlier frame, was another one); a hypothesis
// unmatched is a false positive unless it lies within the gate of an
// object that is not scored (a coasting track behind an occluder, a piece
// of a wall), which is neither; a false positive within the gate of a
// scored object that another hypothesis matched is also a split (one
// object seen as several: the clustering's fragmentation); a miss with a
// hypothesis within the gate that matched another object is also a merge
// (two objects seen as one). Fragmentation: a scored object tracked,
// then missed, then tracked again. Mostly tracked / lost: matched in at
// least 80 % / at most 20 % of the frames in which it was scored.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "metrics/geometry.h"

namespace evade::metrics {

struct TrueObject {
  int id = 0;
  Vec2 centre;
  double radius = 0.0;  // > 0: a disc
  OrientedRect box;     // radius == 0: this rectangle
  bool scored = false;
  double distance_to(Vec2 p) const;  // to the shape, 0 inside
};

struct Hypothesis {
  int64_t id = 0;
  Vec2 centre;
  bool in_range = true;  // false: never a false positive
};

struct MotTotals {
  int64_t frames = 0, objects = 0, matches = 0, misses = 0, false_positives = 0, id_switches = 0;
  int64_t splits = 0;  // false positives on a matched scored object
  int64_t merges = 0;  // misses with another object's hypothesis within the gate
  int64_t fragmentations = 0, mostly_tracked = 0, partially_tracked = 0, mostly_lost = 0;
  double centre_error_sum_m = 0.0;
  double track_s = 0.0;                 // sum over scored matches of the frame's duration
  std::vector<double> time_to_track_s;  // per object tracked at all: first scored -> first matched
  int64_t never_tracked = 0;            // scored at some time, never matched
  double mota() const;
  std::optional<double> motp_m() const;
};

class ClearMot {
 public:
  explicit ClearMot(double gate_m) : gate_m_(gate_m) {}
  // One frame at time t_s lasting dt_s; returns the hypothesis each true
  // object was matched to (scored or not).
  std::map<int, int64_t> add_frame(double t_s, double dt_s, const std::vector<TrueObject>& objects,
                                   const std::vector<Hypothesis>& hyps);
  MotTotals totals() const;

 private:
  struct History {
    std::optional<int64_t> last_hyp;  // any earlier frame
    std::optional<int64_t> prev_frame_hyp;
    int64_t scored = 0, matched = 0;
    bool was_tracked = false, gap_after_track = false;
    std::optional<double> first_scored_s, first_matched_s;
  };
  std::map<int, int64_t> match(const std::vector<TrueObject>& objects, const std::vector<Hypothesis>& hyps);
  void count(double t_s, double dt_s, const std::vector<TrueObject>& objects, const std::vector<Hypothesis>& hyps,
             const std::map<int, int64_t>& matches);

  double gate_m_;
  MotTotals totals_;
  std::map<int, History> history_;
};

}  // namespace evade::metrics
