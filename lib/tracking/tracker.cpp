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

Tracker::Tracker(const TrackerParams& p) : p_(p), dbscan_(1.0, p.dbscan_min_points), dbscan_resolution_(-1.0) {}

void Tracker::add_detection(const GridView& g, const std::vector<int32_t>& cells) {
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
  Detection d;
  d.ellipse = min_bounding_ellipse(corners_, p_.mbe());
  d.num_cells = int(cells.size());
  detections_.push_back(d);
}

void Tracker::detect(const GridView& g) {
  detections_.clear();
  if (dbscan_resolution_ != g.resolution) {
    dbscan_ = GridDbscan(p_.dbscan_eps_m / g.resolution, p_.dbscan_min_points);
    dbscan_resolution_ = g.resolution;
  }
  const auto& clusters = dbscan_.run(g.obstacle, g.width, g.height);
  stats_.clusters += int64_t(clusters.size());
  stats_.noise_cells += dbscan_.noise_cells();
  const int max_extent_cells = int(std::floor(p_.max_cluster_extent_m / g.resolution + 1e-9));
  std::vector<int32_t> tile_cells;
  for (const auto& cells : clusters) {
    int rmin = g.height, rmax = -1, cmin = g.width, cmax = -1;
    for (int32_t i : cells) {
      const int r = i / g.width, c = i % g.width;
      rmin = std::min(rmin, r), rmax = std::max(rmax, r), cmin = std::min(cmin, c), cmax = std::max(cmax, c);
    }
    const bool large = std::max(rmax - rmin + 1, cmax - cmin + 1) > max_extent_cells;
    if (!large || p_.large_cluster == LargeClusterPolicy::kKeep) {
      if (large) ++stats_.large_clusters;
      add_detection(g, cells);
      continue;
    }
    ++stats_.large_clusters;
    if (p_.large_cluster == LargeClusterPolicy::kDrop) {
      ++stats_.large_dropped;
      continue;
    }
    // kSplit: tiles on the odometry frame's lattice, so a wall is cut at
    // the same places from frame to frame and its pieces keep their ids
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
  detect(g);

  // cost = distance between the track's (predicted) centre and the detection's
  const int nt = int(tracks_.size()), nd = int(detections_.size());
  constexpr double kGated = 1e9;  // any gated pair costs more than every admissible assignment
  std::vector<double> cost(size_t(nt) * size_t(nd));
  std::vector<double> dist(cost.size());
  for (int t = 0; t < nt; ++t) {
    const Track& tr = tracks_[size_t(t)];
    double px = tr.cx, py = tr.cy;
    const double gap_s = gap_seconds(g.utime, tr.last_seen_utime);
    const bool predict = p_.predict_with_velocity && tr.has_velocity && gap_s <= p_.max_prediction_gap_s;
    if (predict) {
      px += tr.vx * gap_s;
      py += tr.vy * gap_s;
    }
    for (int d = 0; d < nd; ++d) {
      const Ellipse& e = detections_[size_t(d)].ellipse;
      // The nearer of the predicted and the last centre: a velocity estimate
      // corrupted by a partial occlusion (the visible cells, hence the
      // centre, shift) must not carry a static obstacle's track away.
      double dd = std::hypot(e.cx - px, e.cy - py);
      if (predict) dd = std::min(dd, std::hypot(e.cx - tr.cx, e.cy - tr.cy));
      dist[size_t(t) * nd + d] = dd;
      cost[size_t(t) * nd + d] = dd <= p_.gate_m ? dd : kGated;
    }
  }
  const std::vector<int> assign = kuhn_munkres(cost, nt, nd);
  std::vector<int> det_track(size_t(nd), -1);
  for (int t = 0; t < nt; ++t) {
    const int d = assign[size_t(t)];
    if (d >= 0 && dist[size_t(t) * nd + d] <= p_.gate_m) det_track[size_t(d)] = t;
  }

  std::vector<char> seen(size_t(nt), 0);
  for (int d = 0; d < nd; ++d) {
    const int t = det_track[size_t(d)];
    if (t < 0) continue;
    Track& tr = tracks_[size_t(t)];
    const Ellipse& e = detections_[size_t(d)].ellipse;
    const double gap_s = gap_seconds(g.utime, tr.last_seen_utime);
    if (gap_s > 0.0 && gap_s <= p_.max_prediction_gap_s) {
      const double vx = (e.cx - tr.cx) / gap_s, vy = (e.cy - tr.cy) / gap_s;
      const double k = tr.has_velocity ? p_.velocity_smoothing : 1.0;
      tr.vx = k * vx + (1.0 - k) * tr.vx;
      tr.vy = k * vy + (1.0 - k) * tr.vy;
      tr.has_velocity = true;
    } else {
      tr.has_velocity = false;
    }
    tr.cx = e.cx;
    tr.cy = e.cy;
    tr.last_seen_utime = g.utime;
    tr.missed = 0;
    tr.history.push_back(e);
    while (int(tr.history.size()) > p_.shape_history_frames) tr.history.pop_front();
    seen[size_t(t)] = 1;
  }
  // age every track, count misses, drop the ones unseen for more than K frames
  std::vector<Track> kept;
  kept.reserve(tracks_.size() + size_t(nd));
  std::vector<int> new_index(size_t(nt), -1);
  for (int t = 0; t < nt; ++t) {
    Track& tr = tracks_[size_t(t)];
    ++tr.age;
    if (!seen[size_t(t)]) ++tr.missed;
    if (tr.missed > p_.max_missed_frames) {
      ++stats_.tracks_dropped;
      continue;
    }
    new_index[size_t(t)] = int(kept.size());
    kept.push_back(std::move(tr));
  }
  tracks_ = std::move(kept);
  // unmatched detections start tracks; the table never exceeds max_tracks:
  // the longest-unseen tracks make room first, then new ones are refused
  int unmatched = 0;
  for (int d = 0; d < nd; ++d) unmatched += det_track[size_t(d)] < 0;
  while (int(tracks_.size()) + unmatched > p_.max_tracks) {
    auto worst = std::max_element(tracks_.begin(), tracks_.end(),
                                  [](const Track& a, const Track& b) { return a.missed < b.missed; });
    if (worst == tracks_.end() || worst->missed == 0) break;
    const size_t w = size_t(worst - tracks_.begin());
    for (auto& ni : new_index)
      if (ni == int(w))
        ni = -1;
      else if (ni > int(w))
        --ni;
    tracks_.erase(worst);
    ++stats_.tracks_dropped;
  }
  for (int d = 0; d < nd; ++d) {
    const Detection& det = detections_[size_t(d)];
    const int t = det_track[size_t(d)];
    const Track* tr = nullptr;
    if (t >= 0) {
      tr = &tracks_[size_t(new_index[size_t(t)])];
    } else {
      if (int(tracks_.size()) >= p_.max_tracks) {
        ++stats_.over_track_limit;
        continue;
      }
      Track nt_;
      nt_.id = next_id_++;
      nt_.cx = det.ellipse.cx;
      nt_.cy = det.ellipse.cy;
      nt_.last_seen_utime = g.utime;
      nt_.history.push_back(det.ellipse);
      tracks_.push_back(std::move(nt_));
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
  return out_;
}

}  // namespace evade::tracking
