#include "tracking/tracker.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace evade::tracking {

namespace {
// Seconds from `then` to `now`, in double: any two stamps (INT64_MIN from a
// broken sender, then a real one) give a finite gap instead of overflowing.
double gap_seconds(int64_t now, int64_t then) { return (static_cast<double>(now) - static_cast<double>(then)) * 1e-6; }
}  // namespace

TrackerParams TrackerParams::from_config(const config::Node& s) { return config::load<TrackerParams>(s); }

EpsByRange TrackerParams::eps_cells(double resolution_m) const {
  const double cells = dbscan_eps_m / resolution_m;
  return {cells, dbscan_eps_growth_m_per_m, cells + dbscan_eps_growth_max_m / resolution_m};
}

MbeOptions TrackerParams::mbe() const {
  MbeOptions o;
  o.tolerance = mbe_tolerance;
  o.max_iterations = mbe_max_iterations;
  o.min_semi_axis = min_semi_axis_m;
  return o;
}

double shape_variation(const std::deque<Ellipse>& h, ThetaVariation mode) {
  const size_t m = h.size();
  if (m < 2) return 0.0;
  double ma = 0.0, mb = 0.0, s2 = 0.0, c2 = 0.0;
  for (const auto& e : h) {
    ma += e.a;
    mb += e.b;
    s2 += std::sin(2.0 * e.theta);
    c2 += std::cos(2.0 * e.theta);
  }
  ma /= double(m);
  mb /= double(m);
  const double mtheta = (s2 == 0.0 && c2 == 0.0) ? 0.0 : 0.5 * std::atan2(s2, c2);
  double sum = 0.0;
  for (const auto& e : h) {
    const double da = e.a - ma, db = e.b - mb;
    double dt = wrap_half_pi(e.theta - mtheta);
    if (mode == ThetaVariation::kBoundary) dt *= (e.a - e.b);
    sum += da * da + db * db + dt * dt;
  }
  return sum / double(m - 1);
}

Tracker::Tracker(const TrackerParams& p)
    : p_(p), dbscan_(1.0, p.dbscan_min_points), fine_(1.0, p.dbscan_min_points), dbscan_resolution_(-1.0) {}

Ellipse Tracker::fit(const GridView& g, const std::vector<int32_t>& cells) {
  // The hull of a set of cells is the hull of each row's extreme corners.
  int rmin = g.height, rmax = -1;
  for (int32_t i : cells) rmin = std::min(rmin, i / g.width), rmax = std::max(rmax, i / g.width);
  const size_t rows = size_t(rmax - rmin + 1);
  row_min_.assign(rows, g.width);
  row_max_.assign(rows, -1);
  for (int32_t i : cells) {
    const size_t r = size_t(i / g.width - rmin);
    const int c = i % g.width;
    row_min_[r] = std::min(row_min_[r], c);
    row_max_[r] = std::max(row_max_[r], c);
  }
  corners_.clear();
  const double res = g.resolution;
  for (size_t r = 0; r < rows; ++r) {
    if (row_max_[r] < 0) continue;
    const double y0 = g.origin_y + double(rmin + int(r)) * res;
    const double xl = g.origin_x + row_min_[r] * res, xr = g.origin_x + (row_max_[r] + 1) * res;
    corners_.push_back({xl, y0});
    corners_.push_back({xl, y0 + res});
    corners_.push_back({xr, y0});
    corners_.push_back({xr, y0 + res});
  }
  return min_bounding_ellipse(corners_, p_.mbe());
}

Ellipse Tracker::near_side_corrected(const GridView& g, Ellipse e) const {
  const double lx = e.cx - g.robot_x, ly = e.cy - g.robot_y, l = std::hypot(lx, ly);
  if (!g.has_robot || p_.near_side_shift_b <= 0.0 || !(l > 1e-6)) return e;
  // The LiDAR sees the near side: the body's centre lies behind the visible
  // cells' ellipse. Move the centre away from the sensor and grow the axis
  // nearer the line of sight by as much, so the near boundary stays put.
  const double s = p_.near_side_shift_b * e.b, ux = lx / l, uy = ly / l;
  e.cx += s * ux;
  e.cy += s * uy;
  if (std::fabs(std::cos(e.theta) * ux + std::sin(e.theta) * uy) >= std::sqrt(0.5)) {
    e.a += s;
  } else {
    e.b += s;
    if (e.b > e.a) {
      std::swap(e.a, e.b);
      e.theta = wrap_half_pi(e.theta + M_PI / 2);
    }
  }
  return e;
}

Detection Tracker::make_detection(const GridView& g, const std::vector<int32_t>& cells) {
  Detection d;
  d.ellipse = near_side_corrected(g, fit(g, cells));
  d.num_cells = int(cells.size());
  return d;
}

void Tracker::add_detection(const GridView& g, const std::vector<int32_t>& cells) {
  detections_.push_back(make_detection(g, cells));
}

namespace {
Vec2 cell_centre(const GridView& g, int32_t i) {
  return {g.origin_x + (i % g.width + 0.5) * g.resolution, g.origin_y + (i / g.width + 0.5) * g.resolution};
}
}  // namespace

void Tracker::find_owners(const GridView& g, const std::vector<int32_t>& cells) {
  // confirmed tracks, measured within max_hold_s and owning no other
  // cluster, whose predicted centre lies within reach_m of a cell
  owners_.clear();
  const double reach2 = p_.merge.reach_m * p_.merge.reach_m;
  for (size_t t = 0; t < tracks_.size(); ++t) {
    const Track& tr = tracks_[t];
    if (tr.hits < p_.merge.min_track_frames || tr.claimed) continue;
    if (p_.merge.hold_owners && gap_seconds(g.utime, tr.measured_utime) > p_.merge.max_hold_s) continue;
    for (int32_t i : cells) {
      const Vec2 c = cell_centre(g, i);
      if ((c.x - tr.px) * (c.x - tr.px) + (c.y - tr.py) * (c.y - tr.py) <= reach2) {
        owners_.push_back(int(t));
        break;
      }
    }
  }
  std::sort(owners_.begin(), owners_.end(),
            [&](int a, int b) { return tracks_[size_t(a)].hits > tracks_[size_t(b)].hits; });
}

void Tracker::keep_separated_owners() {
  // two tracks closer than min_separation_m cannot be cut apart: the older one owns
  std::vector<int> kept;
  for (int t : owners_) {
    bool clear = true;
    for (int k : kept)
      clear = clear && std::hypot(tracks_[size_t(t)].px - tracks_[size_t(k)].px,
                                  tracks_[size_t(t)].py - tracks_[size_t(k)].py) >= p_.merge.min_separation_m;
    if (clear) kept.push_back(t);
  }
  owners_ = std::move(kept);
}

bool Tracker::owners_move_apart() const {
  // pieces of one rigid body (a car seen as two tracks) move together
  for (size_t i = 0; i < owners_.size(); ++i)
    for (size_t j = i + 1; j < owners_.size(); ++j) {
      const Track& a = tracks_[size_t(owners_[i])];
      const Track& b = tracks_[size_t(owners_[j])];
      if (std::hypot(a.vx - b.vx, a.vy - b.vy) >= p_.merge.min_relative_speed_mps) return true;
    }
  return false;
}

bool Tracker::partition(const GridView& g, const std::vector<int32_t>& cells) {
  // each cell to the nearest owner's predicted centre; an owner left with
  // fewer than minPts cells is not in this cluster, and the rest re-partition
  while (owners_.size() >= 2) {
    parts_.assign(owners_.size(), {});
    for (int32_t i : cells) {
      const Vec2 c = cell_centre(g, i);
      size_t best = 0;
      double best_d = 1e300;
      for (size_t k = 0; k < owners_.size(); ++k) {
        const Track& tr = tracks_[size_t(owners_[k])];
        const double d = std::hypot(c.x - tr.px, c.y - tr.py);
        if (d < best_d) best_d = d, best = k;
      }
      parts_[best].push_back(i);
    }
    size_t smallest = 0;
    for (size_t k = 1; k < parts_.size(); ++k)
      if (parts_[k].size() < parts_[smallest].size()) smallest = k;
    if (int(parts_[smallest].size()) >= p_.dbscan_min_points) return true;
    owners_.erase(owners_.begin() + long(smallest));
  }
  return false;
}

bool Tracker::explained(const GridView& g, const std::vector<int32_t>& cells) const {
  // every cell lies within reach_m of its nearest owner's body (its last
  // semi-major axis about its predicted centre): nothing else is in the cluster
  for (int32_t i : cells) {
    const Vec2 c = cell_centre(g, i);
    bool near = false;
    for (int t : owners_) {
      const Track& tr = tracks_[size_t(t)];
      near = near || std::hypot(c.x - tr.px, c.y - tr.py) <= tr.history.back().a + p_.merge.reach_m;
    }
    if (!near) return false;
  }
  return true;
}

std::vector<Ellipse> Tracker::held_ellipses(const GridView& g, const std::vector<int32_t>& cells) const {
  // each owner's last shape about its predicted centre, both axes grown to
  // reach the cells nearest to it: together they still cover the cluster
  std::vector<Ellipse> out;
  for (int t : owners_) {
    const Track& tr = tracks_[size_t(t)];
    out.push_back(tr.history.back());
    out.back().cx = tr.px;
    out.back().cy = tr.py;
  }
  const double half_diagonal = g.resolution * std::sqrt(0.5);
  for (int32_t i : cells) {
    const Vec2 c = cell_centre(g, i);
    size_t best = 0;
    double best_d = 1e300;
    for (size_t k = 0; k < out.size(); ++k) {
      const double d = std::hypot(c.x - out[k].cx, c.y - out[k].cy);
      if (d < best_d) best_d = d, best = k;
    }
    out[best].a = std::max(out[best].a, best_d + half_diagonal);
    out[best].b = std::max(out[best].b, best_d + half_diagonal);
  }
  return out;
}

void Tracker::add_owned(const Detection& d, int owner) {
  detections_.push_back(d);
  detections_.back().track = owner;
  tracks_[size_t(owner)].claimed = true;
}

void Tracker::add_cluster(const GridView& g, const std::vector<int32_t>& cells) {
  const size_t first = detections_.size();
  shared_ = false;
  cut_cluster(g, cells);
  for (size_t d = first; d < detections_.size(); ++d) detections_[d].shared = shared_;
}

void Tracker::note_shared(int64_t utime) {
  shared_ = true;
  for (int t : owners_) {
    Track& tr = tracks_[size_t(t)];
    const Track* nearest = nullptr;
    double best = 1e300;
    for (int u : owners_) {
      const Track& o = tracks_[size_t(u)];
      const double d = std::hypot(o.px - tr.px, o.py - tr.py);
      if (u != t && d < best) best = d, nearest = &o;
    }
    if (tr.partner == 0 || gap_seconds(utime, tr.shared_utime) > p_.reid.max_s) {
      // the velocity it came into the merge with, over as many frames as it
      // will be judged on after (a turn just before shows; NaN: none yet)
      tr.pre_vx = tr.pre_vy = std::nan("");
      fit_slope(tr.fixes, size_t(p_.reid.frames), &tr.pre_vx, &tr.pre_vy);
    }
    tr.partner = nearest->id;
    tr.shared_utime = utime;
    tr.clean = 0;
  }
}

void Tracker::cut_cluster(const GridView& g, const std::vector<int32_t>& cells) {
  if (!p_.merge.split) return add_detection(g, cells);
  find_owners(g, cells);
  if (owners_.size() < 2) return add_detection(g, cells);
  note_shared(g.utime);
  // A merge makes the cluster longer than any of its owners was: one object
  // whose second track lingers beside it does not.
  Detection whole = make_detection(g, cells);
  double owner_a = 0.0;
  for (int t : owners_) owner_a = std::max(owner_a, tracks_[size_t(t)].history.back().a);
  const bool grown = whole.ellipse.a >= owner_a + p_.merge.min_growth_m;
  const std::vector<int> all_owners = owners_;
  keep_separated_owners();
  if (grown && owners_move_apart() && partition(g, cells)) {
    ++stats_.merges_split;
    for (size_t k = 0; k < parts_.size(); ++k) {
      if (p_.merge.hold_owners)
        add_owned(make_detection(g, parts_[k]), owners_[k]);
      else
        add_detection(g, parts_[k]);
    }
    return;
  }
  // Inseparable (they overlap) but moving relative to each other: the
  // merged centre is none of theirs, so each owner moves on as predicted.
  owners_ = all_owners;
  if (p_.merge.hold_owners && owners_move_apart() && explained(g, cells)) {
    ++stats_.merges_held;
    const std::vector<Ellipse> held = held_ellipses(g, cells);
    for (size_t k = 0; k < owners_.size(); ++k) {
      Detection d;
      d.ellipse = held[k];
      d.num_cells = int(cells.size());
      d.merged = true;
      add_owned(d, owners_[k]);
    }
    return;
  }
  // One detection; without hold_owners, if it grew, the track it is
  // matched to moves on as predicted.
  whole.merged = grown && p_.merge.hold_motion && !p_.merge.hold_owners;
  detections_.push_back(whole);
  stats_.merges_held += whole.merged;
}

// Whether the cells' bounding box has a side longer than max_cluster_extent_m.
bool Tracker::large(const GridView& g, const std::vector<int32_t>& cells) const {
  int rmin = g.height, rmax = -1, cmin = g.width, cmax = -1;
  for (int32_t i : cells) {
    const int r = i / g.width, c = i % g.width;
    rmin = std::min(rmin, r), rmax = std::max(rmax, r), cmin = std::min(cmin, c), cmax = std::max(cmax, c);
  }
  const int max_extent_cells = int(std::floor(p_.max_cluster_extent_m / g.resolution + 1e-9));
  return std::max(rmax - rmin + 1, cmax - cmin + 1) > max_extent_cells;
}

// kSplit: tiles on the odometry frame's lattice, so a wall is cut at the
// same places from frame to frame and its pieces keep their ids.
void Tracker::add_tiles(const GridView& g, const std::vector<int32_t>& cells) {
  std::map<std::pair<int64_t, int64_t>, std::vector<int32_t>> tiles;
  for (int32_t i : cells) {
    const double x = g.origin_x + (i % g.width + 0.5) * g.resolution;
    const double y = g.origin_y + (i / g.width + 0.5) * g.resolution;
    tiles[{int64_t(std::floor(x / p_.split_tile_m)), int64_t(std::floor(y / p_.split_tile_m))}].push_back(i);
  }
  for (const auto& [key, tcells] : tiles) {
    ++stats_.tiles;
    add_detection(g, tcells);
  }
}

// A large cluster under kSplit. With a radius by range, it is first parted
// into the clusters of the radius at the sensor (fine_'s last run): what a
// far radius joined to a wall (a walker beside it) is an object again, and
// each part large in its own right is tiled.
void Tracker::split_large(const GridView& g, const std::vector<int32_t>& cells, bool by_range) {
  if (!by_range) {
    add_tiles(g, cells);
    return;
  }
  std::map<int32_t, std::vector<int32_t>> parts;  // fine cluster -> its cells here; fine noise is left out
  for (int32_t i : cells)
    if (const int32_t k = fine_.labels()[size_t(i)]; k >= 0) parts[k].push_back(i);
  for (const auto& [k, part] : parts) {
    if (large(g, part))
      add_tiles(g, part);
    else
      add_cluster(g, part);
  }
}

void Tracker::detect(const GridView& g) {
  detections_.clear();
  const EpsByRange eps = p_.eps_cells(g.resolution);
  const bool by_range = eps.by_range();
  if (dbscan_resolution_ != g.resolution) {
    dbscan_ = GridDbscan(eps, p_.dbscan_min_points);
    fine_ = GridDbscan(eps.cells, p_.dbscan_min_points);
    dbscan_resolution_ = g.resolution;
  }
  const double nan = std::nan("");
  const auto& clusters =
      dbscan_.run(g.obstacle, g.width, g.height, g.has_robot ? (g.robot_x - g.origin_x) / g.resolution : nan,
                  g.has_robot ? (g.robot_y - g.origin_y) / g.resolution : nan);
  stats_.clusters += int64_t(clusters.size());
  stats_.noise_cells += dbscan_.noise_cells();
  bool fine_run = false;
  for (const auto& cells : clusters) {
    const bool is_large = large(g, cells);
    if (!is_large || p_.large_cluster == LargeClusterPolicy::kKeep) {
      if (is_large) ++stats_.large_clusters;
      add_cluster(g, cells);
      continue;
    }
    ++stats_.large_clusters;
    if (p_.large_cluster == LargeClusterPolicy::kDrop) {
      ++stats_.large_dropped;
      continue;
    }
    if (by_range && !fine_run) fine_.run(g.obstacle, g.width, g.height), fine_run = true;
    split_large(g, cells, by_range);
  }
}

void Tracker::predict_tracks(int64_t utime) {
  for (Track& tr : tracks_) {
    tr.claimed = false;
    const double gap_s = gap_seconds(utime, tr.last_seen_utime);
    tr.predicted = p_.predict_with_velocity && tr.has_velocity && gap_s <= p_.max_prediction_gap_s;
    tr.px = tr.cx + (tr.predicted ? tr.vx * gap_s : 0.0);
    tr.py = tr.cy + (tr.predicted ? tr.vy * gap_s : 0.0);
  }
}

std::vector<int> Tracker::associate() {
  // cost = distance between the track's (predicted) centre and the detection's
  const int nt = int(tracks_.size()), nd = int(detections_.size());
  constexpr double kGated = 1e9;  // any gated pair costs more than every admissible assignment
  std::vector<double> cost(size_t(nt) * size_t(nd));
  std::vector<double> dist(cost.size());
  for (int t = 0; t < nt; ++t) {
    const Track& tr = tracks_[size_t(t)];
    for (int d = 0; d < nd; ++d) {
      const int bound = detections_[size_t(d)].track;
      if (bound >= 0 || tr.claimed) {  // a detection bound to its owner pairs with it alone
        dist[size_t(t) * nd + d] = bound == t ? 0.0 : kGated;
        cost[size_t(t) * nd + d] = bound == t ? 0.0 : kGated;
        continue;
      }
      const Ellipse& e = detections_[size_t(d)].ellipse;
      // The nearer of the predicted and the last centre: a velocity estimate
      // corrupted by a partial occlusion (the visible cells, hence the
      // centre, shift) must not carry a static obstacle's track away.
      double dd = std::hypot(e.cx - tr.px, e.cy - tr.py);
      if (tr.predicted) dd = std::min(dd, std::hypot(e.cx - tr.cx, e.cy - tr.cy));
      dist[size_t(t) * nd + d] = dd;
      // a track not yet confirmed takes a detection only when no confirmed one wants it
      const double penalty = tr.hits < p_.merge.min_track_frames ? p_.tentative_penalty_m : 0.0;
      cost[size_t(t) * nd + d] = dd <= p_.gate_m ? dd + penalty : kGated;
    }
  }
  const std::vector<int> assign = kuhn_munkres(cost, nt, nd);
  std::vector<int> det_track(size_t(nd), -1);
  for (int t = 0; t < nt; ++t) {
    const int d = assign[size_t(t)];
    if (d >= 0 && dist[size_t(t) * nd + d] <= p_.gate_m) det_track[size_t(d)] = t;
  }
  return det_track;
}

void Tracker::update_velocity(Track& tr, int64_t utime, const Ellipse& e) const {
  const double gap_s = gap_seconds(utime, tr.last_seen_utime);
  if (!(gap_s > 0.0 && gap_s <= p_.max_prediction_gap_s)) {
    tr.has_velocity = false;
    tr.fixes.clear();
  } else if (p_.velocity_window_frames < 2) {
    const double vx = (e.cx - tr.cx) / gap_s, vy = (e.cy - tr.cy) / gap_s;
    const double k = tr.has_velocity ? p_.velocity_smoothing : 1.0;
    tr.vx = k * vx + (1.0 - k) * tr.vx;
    tr.vy = k * vy + (1.0 - k) * tr.vy;
    tr.has_velocity = true;
  }
  tr.fixes.push_back({gap_seconds(utime, 0), e.cx, e.cy});
  const size_t window = size_t(std::max(std::max(2, p_.velocity_window_frames), p_.reid.frames));
  while (tr.fixes.size() > window) tr.fixes.pop_front();
  if (p_.velocity_window_frames < 2) return;
  if (fit_slope(tr.fixes, size_t(p_.velocity_window_frames), &tr.vx, &tr.vy)) tr.has_velocity = true;
}

bool Tracker::fit_slope(const std::deque<Fix>& fixes, size_t n, double* vx, double* vy) {
  // least-squares slope of the centre over the last n fixes' times
  n = std::min(n, fixes.size());
  if (n < 2) return false;
  double mt = 0, mx = 0, my = 0;
  for (size_t i = fixes.size() - n; i < fixes.size(); ++i) mt += fixes[i].t, mx += fixes[i].x, my += fixes[i].y;
  mt /= double(n), mx /= double(n), my /= double(n);
  double stt = 0, stx = 0, sty = 0;
  for (size_t i = fixes.size() - n; i < fixes.size(); ++i) {
    const Fix& f = fixes[i];
    stt += (f.t - mt) * (f.t - mt), stx += (f.t - mt) * (f.x - mx), sty += (f.t - mt) * (f.y - my);
  }
  if (!(stt > 0.0)) return false;
  *vx = stx / stt;
  *vy = sty / stt;
  return true;
}

void Tracker::reidentify(int64_t utime) {
  for (Track& a : tracks_) {
    if (a.partner == 0) continue;
    if (gap_seconds(utime, a.shared_utime) > p_.reid.max_s) a.partner = 0;
    if (a.partner == 0 || a.clean < p_.reid.frames) continue;
    auto b = std::find_if(tracks_.begin(), tracks_.end(), [&](const Track& o) { return o.id == a.partner; });
    if (b == tracks_.end() || b->partner != a.id) {
      if (b == tracks_.end()) a.partner = 0;
      continue;
    }
    if (b->clean < p_.reid.frames) continue;
    a.partner = b->partner = 0;
    // their motions since the parting against their motions before the merge, as they are and exchanged
    double avx, avy, bvx, bvy;
    if (!fit_slope(a.fixes, size_t(p_.reid.frames), &avx, &avy) ||
        !fit_slope(b->fixes, size_t(p_.reid.frames), &bvx, &bvy))
      continue;
    const double kept = std::hypot(avx - a.pre_vx, avy - a.pre_vy) + std::hypot(bvx - b->pre_vx, bvy - b->pre_vy);
    const double exchanged = std::hypot(avx - b->pre_vx, avy - b->pre_vy) + std::hypot(bvx - a.pre_vx, bvy - a.pre_vy);
    if (!(kept - exchanged > p_.reid.margin_mps)) continue;  // NaN (a velocity unknown before): kept
    std::swap(a.id, b->id);
    std::swap(a.age, b->age);
    ++stats_.ids_exchanged;
  }
}

void Tracker::correct_tracks(const GridView& g, const std::vector<int>& det_track) {
  for (size_t d = 0; d < det_track.size(); ++d) {
    const int t = det_track[d];
    if (t < 0) continue;
    Track& tr = tracks_[size_t(t)];
    const Ellipse& e = detections_[d].ellipse;
    if (detections_[d].merged) {
      // a held owner: its detection is its predicted ellipse
      tr.cx = tr.px;
      tr.cy = tr.py;
      tr.last_seen_utime = g.utime;
      tr.missed = 0;
      tr.seen = true;
      continue;
    }
    update_velocity(tr, g.utime, e);
    tr.clean = detections_[d].shared ? 0 : tr.clean + 1;
    tr.cx = e.cx;
    tr.cy = e.cy;
    tr.last_seen_utime = g.utime;
    tr.measured_utime = g.utime;
    tr.missed = 0;
    ++tr.hits;
    tr.history.push_back(e);
    while (int(tr.history.size()) > p_.shape_history_frames) tr.history.pop_front();
    tr.seen = true;
  }
}

std::vector<int> Tracker::prune_tracks(int unmatched) {
  // age every track, count misses, drop the ones unseen for more than K frames
  const int nt = int(tracks_.size());
  std::vector<Track> kept;
  kept.reserve(tracks_.size() + size_t(unmatched));
  std::vector<int> new_index(size_t(nt), -1);
  for (int t = 0; t < nt; ++t) {
    Track& tr = tracks_[size_t(t)];
    ++tr.age;
    if (!tr.seen) ++tr.missed;
    tr.seen = false;
    if (tr.missed > p_.max_missed_frames) {
      ++stats_.tracks_dropped;
      continue;
    }
    new_index[size_t(t)] = int(kept.size());
    kept.push_back(std::move(tr));
  }
  tracks_ = std::move(kept);
  // the table never exceeds max_tracks: the longest-unseen tracks make room
  // for the unmatched detections first, then new ones are refused
  while (int(tracks_.size()) + unmatched > p_.max_tracks) {
    auto worst = std::max_element(tracks_.begin(), tracks_.end(),
                                  [](const Track& a, const Track& b) { return a.missed < b.missed; });
    if (worst == tracks_.end() || worst->missed == 0) break;
    const int w = int(worst - tracks_.begin());
    for (auto& ni : new_index)
      if (ni == w)
        ni = -1;
      else if (ni > w)
        --ni;
    tracks_.erase(worst);
    ++stats_.tracks_dropped;
  }
  return new_index;
}

void Tracker::emit(const GridView& g, const std::vector<int>& det_track, const std::vector<int>& new_index) {
  for (size_t d = 0; d < detections_.size(); ++d) {
    const Detection& det = detections_[d];
    const int t = det_track[d];
    const Track* tr = nullptr;
    if (t >= 0) {
      tr = &tracks_[size_t(new_index[size_t(t)])];
    } else {
      if (int(tracks_.size()) >= p_.max_tracks) {
        ++stats_.over_track_limit;
        continue;
      }
      Track nt;
      nt.id = next_id_++;
      nt.cx = det.ellipse.cx;
      nt.cy = det.ellipse.cy;
      nt.last_seen_utime = g.utime;
      nt.measured_utime = g.utime;
      nt.history.push_back(det.ellipse);
      tracks_.push_back(std::move(nt));
      ++stats_.tracks_born;
      tr = &tracks_.back();
    }
    TrackedObstacle o;
    o.id = tr->id;
    o.ellipse = det.ellipse;
    o.shape_variation = shape_variation(tr->history, p_.shape_variation_theta);
    o.num_cells = det.num_cells;
    o.age = tr->age;
    out_.push_back(o);
  }
}

const std::vector<TrackedObstacle>& Tracker::update(const GridView& g) {
  out_.clear();
  if (last_utime_ >= 0 && g.utime <= last_utime_) {
    // time went backwards (a log loop): start over, ids still never reused
    ++stats_.time_reset;
    stats_.tracks_dropped += int64_t(tracks_.size());
    tracks_.clear();
  }
  last_utime_ = g.utime;
  predict_tracks(g.utime);
  detect(g);
  const std::vector<int> det_track = associate();
  correct_tracks(g, det_track);
  if (p_.reid.enabled) reidentify(g.utime);
  const int unmatched = int(std::count(det_track.begin(), det_track.end(), -1));
  const std::vector<int> new_index = prune_tracks(unmatched);
  emit(g, det_track, new_index);
  return out_;
}

}  // namespace evade::tracking
