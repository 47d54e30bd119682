// The way round settled obstacles that stand on the route.
//
// The MPC sees N dt = 2.5 s ahead and turns at omega_max = 0.5 rad/s (a
// quarter turn takes 3.1 s). In front of an obstacle wider than a bin that
// stands on the route, no swerve within that horizon costs less than
// standing, and the robot stops for good (static_clutter, before this). The
// paper's reference is the route itself; here the route ahead is checked
// against the settled (slow, established) tracks, and where it is blocked
// the reference follows a shortest way round them on a grid instead, back
// to the route past the blockage. Movers stay the D-CBF's alone: their
// predicted ellipses are in the constraints, not in this grid.
//
// Blocked means the planner's own barrier (problem.h, the paper's
// line-ellipse distance minus d_safe) of a settled track's current ellipse
// is below margin_m: the grid keeps the robot where the constraints will
// let it be. Cells with less than comfort_m cost more, so that the way
// round keeps to the middle of a gap and prefers open space to a squeeze
// that the swelling of the predicted ellipses closes later.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "config/fields.h"
#include "planning/ellipse.h"
#include "planning/reference.h"
#include "planning/static_field.h"

namespace evade::planning {

// `planner.detour`; the defaults are config/robot.yaml's.
struct DetourParams {
  bool enabled = true;
  double lookahead_m = 5.0;             // route checked this far ahead of the progress
  double cell_m = 0.1;                  // grid resolution
  double margin_m = 0.05;               // blocked where the barrier h (m, beyond d_safe) is below this
  double comfort_m = 0.5;               // cells with h below this cost more...
  double proximity_cost = 1.0;          // ...up to this much more per metre at h = margin_m (linear in h)
  double deviation_cost = 0.5;          // cost factor per metre of distance from the route (stay near it)
  double rejoin_m = 1.0;                // back on the route this far past the blocked stretch
  double pad_m = 2.5;                   // grid beyond the box of robot and rejoin point
  double max_obstacle_speed_mps = 0.2;  // settled: slower than this...
  double min_track_age_s = 1.0;         // ...and tracked this long
  double blocked_cost = 50.0;           // cost factor of a blocked cell (a squeeze through it is a costly way)
  double keep_side_discount = 0.5;      // cost factor of cells along the previous way round (no flip-flop)
  double smoothing_m = 0.3;             // half-width of the moving average over the grid path
  int max_cells = 40000;                // a larger grid is not searched (the route is followed as it is)
  double min_offset_m = 0.8;            // a way round within this of the route is left to the MPC
  double memory_s = 3.0;                // s a settled track's last ellipse is kept (SettledMemory)
  // Slow leaders: a track ahead going the route's way slower than this
  // (faster than max_obstacle_speed_mps)...
  double leader_max_speed_mps = 0.6;
  double leader_max_angle_rad = 30.0 * M_PI / 180.0;  // ...within this of the route's heading (config: degrees)...
  double leader_sweep_s = 2.0;                        // ...enters the grid as its ellipse swept this far ahead
  // An oncoming mover (within this of the route's reverse heading) enters
  // the grid swept up to the robot, at most oncoming_sweep_s ahead (0 =
  // off), if its uncertainty inflation at k = 0 is at most
  // oncoming_max_sigma_m: a static object the robot drives up to reads as
  // oncoming while its visible part changes, and with the shape change
  // comes a large sigma.
  double oncoming_max_angle_rad = 30.0 * M_PI / 180.0;  // config: degrees
  double oncoming_sweep_s = 4.0;
  double oncoming_max_sigma_m = 0.25;
  double min_mover_age_s = 0.5;  // a leader or oncoming mover is swept once tracked this long

  template <class V>
  void fields(V& v) {
    v.field("enabled", enabled);
    v.field("lookahead_m", lookahead_m, config::between(0.0, 100.0));
    v.field("cell_m", cell_m, config::between(0.01, 1.0));
    v.field("margin_m", margin_m, config::between(0.0, 10.0));
    v.field("comfort_m", comfort_m, config::between(margin_m + 1e-3, 20.0));
    v.field("proximity_cost", proximity_cost, config::between(0.0, 1e3));
    v.field("deviation_cost", deviation_cost, config::between(0.0, 1e3));
    v.field("rejoin_m", rejoin_m, config::between(0.0, 100.0));
    v.field("pad_m", pad_m, config::between(0.0, 100.0));
    v.field("max_obstacle_speed_mps", max_obstacle_speed_mps, config::between(0.0, 100.0));
    v.field("min_track_age_s", min_track_age_s, config::between(0.0, 3600.0));
    v.field("blocked_cost", blocked_cost, config::between(1.0, 1e6));
    v.field("keep_side_discount", keep_side_discount, config::between(0.01, 1.0));
    v.field("smoothing_m", smoothing_m, config::between(0.0, 10.0));
    v.field("max_cells", max_cells, config::between(1, 10000000));
    v.field("min_offset_m", min_offset_m, config::between(0.0, 100.0));
    v.field("leader_max_speed_mps", leader_max_speed_mps, config::between(0.0, 100.0));
    v.convert("leader_max_angle_deg", leader_max_angle_rad, config::degrees_as_radians(config::between(0.0, 90.0)));
    v.field("leader_sweep_s", leader_sweep_s, config::between(0.0, 60.0));
    v.convert("oncoming_max_angle_deg", oncoming_max_angle_rad, config::degrees_as_radians(config::between(0.0, 90.0)));
    v.field("oncoming_sweep_s", oncoming_sweep_s, config::between(0.0, 60.0));
    v.field("oncoming_max_sigma_m", oncoming_max_sigma_m, config::between(0.0, 100.0));
    v.field("min_mover_age_s", min_mover_age_s, config::between(0.0, 3600.0));
    v.field("memory_s", memory_s, config::between(0.0, 3600.0));
  }
};

// The settled obstacles of the last memory_s, by track id. A large object
// is seen as pieces whose ids come and go and whose centres jump as the
// view changes (a parked car's end, then its side: apparent speeds up to
// 1.9 m/s for a few frames); each piece's last settled ellipse is kept for
// memory_s after its id is dropped, so that the grid does not open a way
// through the car every time a piece goes. An id seen moving is forgotten
// at once: a remembered ghost beside the route bent the reference into the
// walkers' way in mixed_street.
class SettledMemory {
 public:
  explicit SettledMemory(double memory_s) : memory_us_(static_cast<int64_t>(memory_s * 1e6)) {}
  // The settled tracks seen at utime (id, ellipse) and the ids seen moving
  // (forgotten at once: a walker who stood and walks on, a cluster merged
  // with a passer-by); older entries expire.
  void update(int64_t utime, const std::vector<std::pair<int64_t, Ellipse>>& settled,
              const std::vector<int64_t>& moving = {});
  std::vector<Ellipse> obstacles() const;
  size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    Ellipse ellipse;
    int64_t last_seen_us;
  };
  int64_t memory_us_;
  std::map<int64_t, Entry> entries_;
};

class DetourPlanner {
 public:
  enum class Result {
    kClear,   // the route ahead is free: follow it
    kDetour,  // the way round is in the output
    kNoWay,   // blocked, but no rejoin point within a grid's reach (or the route's end is blocked), no gap,
              // or the grid is too large
  };

  DetourPlanner(DetourParams p, double d_safe) : p_(p), d_safe_(d_safe) {}

  // From the robot at (px, py) along `route` (its progress already
  // updated): kDetour with the polyline robot -> way round -> rejoin point
  // -> the rest of the route in (x, y); otherwise (x, y) are left empty.
  Result plan(const RouteFollower& route, double px, double py, const std::vector<Ellipse>& obstacles,
              std::vector<double>* x, std::vector<double>* y);

  // The smallest barrier h over the obstacles at (px, py) (m; a large value
  // when there are none), and over the static field when one is set.
  double clearance(const std::vector<Ellipse>& obstacles, double px, double py) const;

  // Static structure by its cells (static_field.h), null for none. Its
  // clearance at a cell is the field less `radius` (the footprint's disc)
  // and the field's d_safe, plus margin_m: static cells do not swell, so
  // only a cell where the robot cannot stand is blocked.
  void set_field(std::shared_ptr<const StaticField> field, double radius) {
    field_ = std::move(field);
    field_radius_ = radius;
  }

  // Cells expanded by the last search (0 when none ran).
  int last_expanded() const { return last_expanded_; }

 private:
  DetourParams p_;
  double d_safe_;
  std::shared_ptr<const StaticField> field_;
  double field_radius_ = 0;
  std::vector<double> prev_x_, prev_y_;  // the previous way round (hysteresis)
  int last_expanded_ = 0;
};

}  // namespace evade::planning
