// Obstacle parameterization and tracking (paper III-B): DBSCAN clusters of
// obstacle cells -> minimum bounding ellipses over the cells' corners ->
// Kuhn-Munkres association on centre distance with gate d_max -> stable ids
// and the shape-variation indicator Xi_eta.
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "config/config.h"
#include "config/fields.h"
#include "tracking/dbscan.h"
#include "tracking/geometry.h"

namespace evade::tracking {

enum class LargeClusterPolicy { kKeep, kDrop, kSplit };
enum class ThetaVariation { kRaw, kBoundary };

// Two tracked objects that come within eps of each other form one DBSCAN
// cluster. With `split`, a cluster that holds the predicted centres of two
// or more confirmed tracks and is longer than any of them was is cut into
// one part per track, each cell going to the nearest predicted centre. One
// whose owners overlap (cannot be cut) but move relative to each other is,
// with `hold_owners`, explained by its owners' motion: each owner is its
// own detection at its predicted centre, and every detection made for an
// owner (held or cut) is bound to it. Without it (the default), the track
// matched to such a grown cluster moves on as predicted (`hold_motion`).
struct MergeSplitParams {
  bool split = true;
  int min_track_frames = 5;             // a track counts once matched in this many frames
  double reach_m = 0.3;                 // its predicted centre lies within this of one of the cluster's cells
  double min_separation_m = 0.4;        // owners' predicted centres at least this far apart (else the older one counts)
  double min_growth_m = 0.1;            // the cluster's semi-major axis exceeds every owner's last one by this
  double min_relative_speed_mps = 0.3;  // and two of them move apart at least this fast (not one rigid body)
  bool hold_motion = true;              // a grown cluster that cannot be cut: its track moves on as predicted
  bool hold_owners = false;             // instead: every owner moves on as predicted, its detection bound to it
  double max_hold_s = 0.5;              // with hold_owners: a track unmeasured for longer owns no cells

  template <class V>
  void fields(V& v) {
    v.field("split", split);
    v.field("min_track_frames", min_track_frames, config::between(1, 1000));
    v.field("reach_m", reach_m, config::between(0.0, 10.0));
    v.field("min_separation_m", min_separation_m, config::between(0.0, 10.0));
    v.field("min_growth_m", min_growth_m, config::between(0.0, 10.0));
    v.field("min_relative_speed_mps", min_relative_speed_mps, config::between(0.0, 100.0));
    v.field("hold_motion", hold_motion);
    v.field("hold_owners", hold_owners);
    v.field("max_hold_s", max_hold_s, config::between(0.0, 60.0));
  }
};

// Two tracks that shared a cluster (a merge, cut or not) may come out of it
// on each other's object: the merged centre drags their velocities, and a
// walker that turned just before has none worth predicting with. Once both
// have been measured in clusters of their own for `frames` frames, their
// velocities since the parting are compared with their velocities before
// the merge; if the two ids explain the motions better exchanged (the sum
// of the velocity differences lower by `margin_mps`), they are exchanged.
struct ReidParams {
  bool enabled = false;     // exchange the ids of two tracks whose motions through a merge say so
  int frames = 2;           // judged once both have this many measured frames in clusters of their own
  double margin_mps = 0.8;  // exchanged only when the sum of velocity differences drops by this much
  double max_s = 2.0;       // a merge older than this (one of its tracks never measured again) is forgotten

  template <class V>
  void fields(V& v) {
    v.field("enabled", enabled);
    v.field("frames", frames, config::between(2, 100));
    v.field("margin_mps", margin_mps, config::between(0.0, 100.0));
    v.field("max_s", max_s, config::between(0.0, 60.0));
  }
};

struct TrackerParams {
  double dbscan_eps_m = 0.15;                 // DBSCAN neighbourhood radius (0.15 at 0.1 m cells: the 8 neighbours)
  double dbscan_eps_growth_m_per_m = 0.0135;  // the radius grows by this per m of range from the robot...
  double dbscan_eps_growth_max_m = 0.1;       // ...by at most this (EpsByRange, dbscan.h)
  int dbscan_min_points = 3;                  // DBSCAN minPts (the cell itself included)
  double gate_m = 0.8;                        // d_max: farthest centre distance accepted as the same obstacle
  int max_missed_frames = 10;                 // K: a track unseen for more frames is dropped
  int shape_history_frames = 10;              // m: frames in the shape-variation window
  int max_tracks = 256;                       // hard bound on the track table
  double max_cluster_extent_m = 3.0;          // a cluster whose bounding box side exceeds this is "large"
  LargeClusterPolicy large_cluster = LargeClusterPolicy::kSplit;
  double split_tile_m = 1.5;          // kSplit: tile size on the odometry-frame lattice
  double mbe_tolerance = 1e-5;        // MbeOptions::tolerance (geometry.h)
  int mbe_max_iterations = 2000;      // MbeOptions::max_iterations
  double min_semi_axis_m = 0.05;      // MbeOptions::min_semi_axis
  bool predict_with_velocity = true;  // cost = min(distance to predicted centre, to last centre)
  double velocity_smoothing = 0.5;    // weight of the newest centre difference in the velocity estimate
  int velocity_window_frames =
      10;                          // >= 2: velocity = least-squares slope of the last this many centres; else smoothing
  double near_side_shift_b = 0.3;  // centre moved away from the robot by this times the semi-minor axis
  double tentative_penalty_m = 0.3;   // added to the cost of a track matched in fewer than merge.min_track_frames
  double max_prediction_gap_s = 1.0;  // beyond this gap the last centre is used as is
  ThetaVariation shape_variation_theta = ThetaVariation::kBoundary;
  MergeSplitParams merge;
  ReidParams reid;

  // The minimum bounding ellipse's options from the three mbe keys.
  MbeOptions mbe() const;
  // The DBSCAN radius (all three dbscan_eps keys) in cells of `resolution_m`.
  EpsByRange eps_cells(double resolution_m) const;

  template <class V>
  void fields(V& v) {
    v.field("dbscan_eps_m", dbscan_eps_m, config::positive());
    v.field("dbscan_eps_growth_m_per_m", dbscan_eps_growth_m_per_m, config::between(0.0, 1.0));
    v.field("dbscan_eps_growth_max_m", dbscan_eps_growth_max_m, config::between(0.0, 1.0));
    v.field("dbscan_min_points", dbscan_min_points, config::between(1, 10000));
    v.field("gate_m", gate_m, config::positive());
    v.field("max_missed_frames", max_missed_frames, config::between(0, 1000));
    v.field("shape_history_frames", shape_history_frames, config::between(2, 1000));
    v.field("max_tracks", max_tracks, config::between(1, 100000));
    v.field("max_cluster_extent_m", max_cluster_extent_m, config::positive());
    v.choice("large_cluster", large_cluster,
             config::Choices<LargeClusterPolicy>{{"keep", LargeClusterPolicy::kKeep},
                                                 {"drop", LargeClusterPolicy::kDrop},
                                                 {"split", LargeClusterPolicy::kSplit}});
    v.field("split_tile_m", split_tile_m, config::positive());
    v.field("mbe_tolerance", mbe_tolerance, config::between(1e-12, 0.5));
    v.field("mbe_max_iterations", mbe_max_iterations, config::between(1, 1000000));
    v.field("min_semi_axis_m", min_semi_axis_m, config::positive());
    v.field("predict_with_velocity", predict_with_velocity);
    v.field("velocity_smoothing", velocity_smoothing, config::between(0.0, 1.0));
    v.field("velocity_window_frames", velocity_window_frames, config::between(0, 1000));
    v.field("near_side_shift_b", near_side_shift_b, config::between(0.0, 2.0));
    v.field("tentative_penalty_m", tentative_penalty_m, config::between(0.0, 100.0));
    v.field("max_prediction_gap_s", max_prediction_gap_s, config::between(0.0, 60.0));
    v.choice("shape_variation_theta", shape_variation_theta,
             config::Choices<ThetaVariation>{{"raw", ThetaVariation::kRaw}, {"boundary", ThetaVariation::kBoundary}});
    v.section("merge", merge);
    v.section("reid", reid);
  }

  static TrackerParams from_config(const config::Node& section);
};

// One grid's obstacle layer, as the tracker needs it.
struct GridView {
  int64_t utime = 0;
  double origin_x = 0.0, origin_y = 0.0, resolution = 0.1;
  int width = 0, height = 0;
  const int8_t* obstacle = nullptr;  // width * height, row-major
  bool has_robot = false;            // robot_x, robot_y known (near-side correction)
  double robot_x = 0.0, robot_y = 0.0;
};

struct Detection {
  Ellipse ellipse;
  int num_cells = 0;
  bool merged = false;  // an owner's predicted ellipse, no measurement (MergeSplitParams::hold_motion)
  int track = -1;       // the owner it is bound to (index into the track table), -1: associated by cost
  bool shared = false;  // made from a cluster that two or more confirmed tracks owned
};

struct TrackedObstacle {
  int64_t id = 0;
  Ellipse ellipse;
  double shape_variation = 0.0;  // Xi_eta
  int num_cells = 0;
  int age = 0;  // frames since birth
};

struct TrackerStats {
  int64_t clusters = 0;
  int64_t noise_cells = 0;
  int64_t large_clusters = 0;
  int64_t large_dropped = 0;
  int64_t tiles = 0;
  int64_t tracks_born = 0;
  int64_t tracks_dropped = 0;
  int64_t over_track_limit = 0;
  int64_t time_reset = 0;
  int64_t merges_split = 0;   // clusters cut into one part per owning track
  int64_t merges_held = 0;    // merged clusters that could not be cut (their owners moved on as predicted)
  int64_t ids_exchanged = 0;  // pairs of tracks whose ids were exchanged after a merge (ReidParams)
};

// Shape-variation indicator (paper Xi_eta): sum over the window of
// ||eta_i - mean(eta)||^2 / (m - 1), eta = (a, b, theta). theta is an axis
// (period pi): its mean is the doubled-angle circular mean and deviations are
// wrapped. With kBoundary the angle deviation enters as (a - b) * dtheta, the
// displacement it causes on the ellipse, so the ill-defined axis of a
// near-circle does not read as a shape change (m^2 throughout).
double shape_variation(const std::deque<Ellipse>& history, ThetaVariation mode);

class Tracker {
 public:
  explicit Tracker(const TrackerParams& p);

  // Clusters, fits and associates one grid; returns the obstacles seen in it.
  const std::vector<TrackedObstacle>& update(const GridView& grid);

  const std::vector<Detection>& detections() const { return detections_; }
  size_t num_tracks() const { return tracks_.size(); }
  int64_t next_id() const { return next_id_; }
  const TrackerStats& stats() const { return stats_; }
  const TrackerParams& params() const { return p_; }

 private:
  struct Fix {
    double t, x, y;  // s (any origin), observed centre
  };
  struct Track {
    int64_t id;
    double cx, cy;  // last observed centre
    double vx = 0, vy = 0;
    bool has_velocity = false;
    int64_t last_seen_utime;
    int64_t measured_utime;  // last frame with a measurement (not a held prediction)
    int missed = 0;
    int age = 0;
    int hits = 1;                 // frames it was matched in (birth included)
    double px = 0, py = 0;        // this frame's predicted centre
    bool predicted = false;       // px, py extrapolated with the velocity
    bool seen = false;            // matched in this frame
    bool claimed = false;         // owns a cluster's cells in this frame
    std::deque<Ellipse> history;  // last m ellipses
    std::deque<Fix> fixes;        // last velocity_window_frames centres since the last long gap

    // ReidParams: the track it last shared a cluster with (its id, 0: none),
    // when, its own velocity before that merge, and the frames it has been
    // measured in a cluster of its own since
    int64_t partner = 0, shared_utime = 0;
    double pre_vx = 0, pre_vy = 0;
    int clean = 0;
  };
  // One frame, in order: predicted centres, clusters (merges split), the
  // assignment (det_track[d]: track index or -1), the matched tracks'
  // update, ageing and dropping (returns old -> new index), the output.
  void predict_tracks(int64_t utime);
  void detect(const GridView& grid);
  bool large(const GridView& grid, const std::vector<int32_t>& cells) const;
  void add_tiles(const GridView& grid, const std::vector<int32_t>& cells);
  void split_large(const GridView& grid, const std::vector<int32_t>& cells, bool by_range);
  std::vector<int> associate();
  void update_velocity(Track& track, int64_t utime, const Ellipse& e) const;
  // least-squares slope of the last n fixes' centres over their times; false if undefined
  static bool fit_slope(const std::deque<Fix>& fixes, size_t n, double* vx, double* vy);
  void correct_tracks(const GridView& grid, const std::vector<int>& det_track);
  void note_shared(int64_t utime);  // owners_ shared one cluster: each one's partner and velocity before
  void reidentify(int64_t utime);   // exchange the ids of parted partners whose motions say so
  std::vector<int> prune_tracks(int unmatched);
  void emit(const GridView& grid, const std::vector<int>& det_track, const std::vector<int>& new_index);

  Ellipse fit(const GridView& grid, const std::vector<int32_t>& cells);
  Ellipse near_side_corrected(const GridView& grid, Ellipse e) const;
  Detection make_detection(const GridView& grid, const std::vector<int32_t>& cells);
  void add_detection(const GridView& grid, const std::vector<int32_t>& cells);
  void add_cluster(const GridView& grid, const std::vector<int32_t>& cells);
  void cut_cluster(const GridView& grid, const std::vector<int32_t>& cells);
  void find_owners(const GridView& grid, const std::vector<int32_t>& cells);  // -> owners_, oldest first
  void keep_separated_owners();
  bool owners_move_apart() const;
  bool partition(const GridView& grid, const std::vector<int32_t>& cells);  // owners_ -> parts_
  bool explained(const GridView& grid, const std::vector<int32_t>& cells) const;
  void add_owned(const Detection& d, int owner);
  std::vector<Ellipse> held_ellipses(const GridView& grid, const std::vector<int32_t>& cells) const;  // per owner

  TrackerParams p_;
  GridDbscan dbscan_;
  GridDbscan fine_;  // with a radius by range: the radius at the sensor, which cuts structure
  double dbscan_resolution_;
  std::vector<Detection> detections_;
  std::vector<Track> tracks_;
  std::vector<TrackedObstacle> out_;
  int64_t next_id_ = 1;
  int64_t last_utime_ = -1;
  TrackerStats stats_;
  // scratch
  std::vector<int32_t> row_min_, row_max_;
  std::vector<Vec2> corners_;
  std::vector<int> owners_;
  bool shared_ = false;  // the cluster being added had two or more owners
  std::vector<std::vector<int32_t>> parts_;
};

}  // namespace evade::tracking
