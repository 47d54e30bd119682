// The planner's static structure state (mode evade with
// static_field.enabled): the elevation maps kept, the distance field of
// this cycle (static_field.h) and the static tracks it stands for.
//
// Each cycle `update` builds the field from the kept map nearest in time to
// the predictions: its static cells are the map's obstacle cells outside
// every moving track's ellipse (faster than max_speed_mps; grown by
// mover_margin_m) that lie in an 8-connected patch of static cells at
// least min_structure_m long (walls, door frames, parked cars;
// StaticFieldParams). Static by the map, not by the track: a slow track's
// cells stay whatever its age (a wall's tile under a new id is still
// wall). A smaller patch (a person, a bin, a post, a mover's cells outside
// its ellipse) is no structure: whatever of it is tracked stays its
// ellipse. A slow track in the last OBSTACLES (a coasting track's cells
// may be hidden) whose own cells are structure (at least
// min_structure_share of the obstacle cells in its ellipse; tracked less
// than min_track_age_s, whose speed is not known yet, they must also span
// min_structure_m: no person) `stands_for` by them: it leaves the ellipse constraints (`apply`) and the detour
// grid, which read the field instead. A person standing against a wall,
// whose ellipse takes in some of the wall's cells, keeps its ellipse.
//
// No clock and no bus: the planner core gates the maps' arrival and counts
// what `update` returns.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "evade/grid_map_t.hpp"
#include "evade/obstacle_list_t.hpp"
#include "evade/prediction_list_t.hpp"
#include "planning/problem.h"
#include "planning/static_field.h"

namespace evade::planning {

// How far a plan's rollout (`states`, 3 (N + 1)) takes the footprint
// into static structure beyond where it starts, over the field obstacles
// of pb and k >= 1 (0 without a field), from one evaluation of the field
// per step:
// - margin: into the field's margin, max(0, min(h_0, 0) - h_k). A
//   recovery plan that drives into a wall to get away from a walker
//   trades a contact of its own making for one that may not come.
// - body: the discs into the structure's cells themselves (h below
//   -d_safe), max(0, min(h_0, -d_safe) - h_k). Positive only where
//   margin is too.
struct StructureDepth {
  double margin = 0.0;
  double body = 0.0;
};
StructureDepth structure_depth(const Problem& pb, const std::vector<double>& states);
// structure_depth's margin alone.
double structure_intrusion(const Problem& pb, const std::vector<double>& states);

class StaticStructure {
 public:
  explicit StaticStructure(StaticFieldParams p) : p_(p) {}

  // Keeps `m` (the last kMapsKept: a map and the predictions made from its
  // scan arrive about 1 ms apart).
  void keep_map(const evade::grid_map_t& m);
  // Forgets the maps, the field and the remembered structure (a new
  // odometry epoch).
  void clear();

  // What one cycle's update found.
  enum class Update {
    kBuilt,    // a field from a map within map_max_age_s of the odometry
    kStale,    // no such map: no field, every track by its ellipse
    kInvalid,  // the map is malformed: no field
  };
  struct Inputs {
    int64_t odometry_utime = 0;
    FieldWindow window;  // where the field is read (StaticField::build; default: the whole map)
    const evade::prediction_list_t* predictions = nullptr;  // null: none yet
    const evade::obstacle_list_t* observed = nullptr;       // the last OBSTACLES (null: none)
    std::function<double(int64_t id)> track_age_s;          // how long a track id has been listed
  };
  // What the LiDAR cannot see is not free: within blind_radius_m of the
  // robot (its min_range_m, where returns are dropped) a map has no cells,
  // so the structure cells of the last field that lie there are added to
  // the map's obstacle cells before the field is built (a door's edge
  // the robot passes within 0.4 m of stays in the field). Inside the disc
  // the memory is what the maps saw before the cell came into it: a cell
  // that was structure in the last blind_memory_frames maps in a row (a
  // cell that flickers on at a wall's edge in one scan as the disc reaches
  // it would otherwise stand there for as long as the robot does); outside
  // it the map decides again.
  Update update(const Inputs& in);

  // This cycle's field (null without one).
  const std::shared_ptr<const StaticField>& field() const { return field_; }
  // True when the track `id` is static structure this cycle: its cells
  // stand for it, not its ellipse.
  bool stands_for(int64_t id) const;
  // The static tracks leave pb's ellipse constraints and the field enters
  // them (one obstacle with `decay`, at the robot's (x0, y0)); nothing
  // without a field. With no static cell within max_distance_m of (x0, y0)
  // the field is flat where the robot can reach and stays out: a
  // constraint that cannot be active changes nothing but the solver's
  // rounding, and a street of walkers keeps the problem it has without it.
  void apply(double x0, double y0, double decay, Problem* pb) const;

  static constexpr size_t kMapsKept = 3;

 private:
  const evade::grid_map_t* nearest_map(int64_t utime) const;
  static bool observed(int64_t id, const Inputs& in);
  // `map` with the remembered structure cells inside its blind zone
  // added to its obstacle cells, in *with; false (and *with untouched)
  // when there are none.
  bool add_remembered(const evade::grid_map_t& map, evade::grid_map_t* with) const;
  // Whether a lattice cell's centre, placed in `map` from its origin (whose
  // lattice cell is `o`, StaticField::lattice_origin), lies within
  // blind_radius_m of the map's robot position.
  bool in_blind_disc(const evade::grid_map_t& map, const StaticField::LatticeCell& o,
                     const StaticField::LatticeCell& cell) const;
  // The remembered cells after this cycle's field (of `map`; once per map).
  void remember(const evade::grid_map_t& map);

  StaticFieldParams p_;
  std::deque<evade::grid_map_t> maps_;
  std::shared_ptr<const StaticField> field_;
  std::vector<int64_t> static_ids_;                   // sorted
  std::vector<StaticField::LatticeCell> remembered_;  // the blind disc's cells, and those that may enter it
  double remembered_res_ = 0;                         // their lattice's resolution (m)
  // structure cells outside the disc, sorted, each with how many maps in a
  // row it has been structure
  std::vector<std::pair<StaticField::LatticeCell, int>> seen_;
  int64_t remembered_utime_ = -1;  // the map remember() last took
};

}  // namespace evade::planning
