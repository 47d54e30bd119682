#include "metrics/perception_metrics.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "bus/core.h"
#include "evade/obstacle_list_t.hpp"
#include "evade/odometry_t.hpp"
#include "evade/prediction_list_t.hpp"
#include "evade/sim_truth_t.hpp"

namespace evade::metrics {

PerceptionParams PerceptionParams::from_config(const config::Node& s) { return config::load<PerceptionParams>(s); }

namespace {

struct Pose {
  double x = 0.0, y = 0.0, yaw = 0.0;
};

double lerp_angle(double a, double b, double f) { return a + f * std::remainder(b - a, 2.0 * M_PI); }

// The world at one time: the robot, the obstacles, and the odometry pose.
struct Snapshot {
  Pose robot_world, robot_odom;
  std::vector<evade::sim_obstacle_t> obstacles;  // world frame, interpolated
  std::vector<int32_t> returns;                  // -1: not recorded
  // World -> odometry frame (exact at this time: odometry drift removed).
  Vec2 to_odom(Vec2 w) const {
    const double c = std::cos(robot_world.yaw), s = std::sin(robot_world.yaw);
    const double rx = c * (w.x - robot_world.x) + s * (w.y - robot_world.y);
    const double ry = -s * (w.x - robot_world.x) + c * (w.y - robot_world.y);
    const double co = std::cos(robot_odom.yaw), so = std::sin(robot_odom.yaw);
    return {robot_odom.x + co * rx - so * ry, robot_odom.y + so * rx + co * ry};
  }
  double yaw_to_odom(double yaw) const { return yaw + robot_odom.yaw - robot_world.yaw; }
};

class Timeline {
 public:
  Timeline(std::vector<evade::sim_truth_t> truth, std::vector<evade::odometry_t> odom)
      : truth_(std::move(truth)), odom_(std::move(odom)) {}

  // False outside the truth's time span.
  bool at(int64_t utime, Snapshot* s) const {
    auto hi = std::lower_bound(truth_.begin(), truth_.end(), utime,
                               [](const evade::sim_truth_t& t, int64_t u) { return t.utime < u; });
    if (hi == truth_.end()) return false;
    if (hi->utime != utime && hi == truth_.begin()) return false;
    const evade::sim_truth_t& b = *hi;
    const evade::sim_truth_t& a = hi->utime == utime ? b : *(hi - 1);
    const double f = b.utime == a.utime ? 1.0 : double(utime - a.utime) / double(b.utime - a.utime);
    s->robot_world = {a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), lerp_angle(a.yaw, b.yaw, f)};
    s->obstacles = b.obstacles;
    for (size_t i = 0; i < s->obstacles.size() && i < a.obstacles.size(); ++i) {
      s->obstacles[i].x = a.obstacles[i].x + f * (b.obstacles[i].x - a.obstacles[i].x);
      s->obstacles[i].y = a.obstacles[i].y + f * (b.obstacles[i].y - a.obstacles[i].y);
    }
    s->returns = a.lidar_returns;
    s->robot_odom = odom_at(utime, s->robot_world);
    return true;
  }

 private:
  Pose odom_at(int64_t utime, const Pose& fallback) const {
    auto it = std::upper_bound(odom_.begin(), odom_.end(), utime,
                               [](int64_t u, const evade::odometry_t& o) { return u < o.utime; });
    if (it == odom_.begin()) return fallback;  // no odometry yet: the frames agree
    --it;
    // Dead-reckon from the last sample to `utime` (at most one period).
    const double dt = (utime - it->utime) * 1e-6;
    return {it->x + it->v * dt * std::cos(it->yaw), it->y + it->v * dt * std::sin(it->yaw), it->yaw + it->omega * dt};
  }
  std::vector<evade::sim_truth_t> truth_;
  std::vector<evade::odometry_t> odom_;
};

struct Decoded {
  std::vector<evade::sim_truth_t> truth;
  std::vector<evade::odometry_t> odom;
  std::vector<evade::obstacle_list_t> lists;
  std::vector<evade::prediction_list_t> predictions;
};

Decoded decode(const std::vector<bus::LogEvent>& events, const std::string& obstacles, const std::string& predictions) {
  Decoded d;
  for (const auto& e : events) {
    if (e.channel == "SIM_TRUTH") {
      evade::sim_truth_t t;
      if (bus::decode(e.data.data(), e.data.size(), &t)) d.truth.push_back(std::move(t));
    } else if (e.channel == "ODOMETRY") {
      evade::odometry_t o;
      if (bus::decode(e.data.data(), e.data.size(), &o)) d.odom.push_back(o);
    } else if (e.channel == obstacles) {
      evade::obstacle_list_t l;
      if (bus::decode(e.data.data(), e.data.size(), &l)) d.lists.push_back(std::move(l));
    } else if (e.channel == predictions) {
      evade::prediction_list_t p;
      if (bus::decode(e.data.data(), e.data.size(), &p)) d.predictions.push_back(std::move(p));
    }
  }
  if (d.truth.empty()) throw std::runtime_error("no SIM_TRUTH in the log: perception metrics need a simulated run");
  auto by_time = [](const auto& a, const auto& b) { return a.utime < b.utime; };
  std::stable_sort(d.truth.begin(), d.truth.end(), by_time);
  std::stable_sort(d.odom.begin(), d.odom.end(), by_time);
  std::stable_sort(d.lists.begin(), d.lists.end(), by_time);
  return d;
}

double object_size(const evade::sim_obstacle_t& o) {
  return o.shape == "box" ? std::max(o.length, o.width) : 2.0 * o.radius;
}

TrueObject true_object(const Snapshot& s, size_t i, const PerceptionParams& p) {
  const evade::sim_obstacle_t& o = s.obstacles[i];
  TrueObject t;
  t.id = o.id;
  t.centre = s.to_odom({o.x, o.y});
  if (o.shape == "box")
    t.box = OrientedRect{t.centre, s.yaw_to_odom(o.yaw), o.length, o.width};
  else
    t.radius = o.radius;
  const int32_t returns = i < s.returns.size() ? s.returns[i] : -1;
  const bool visible = returns < 0 || returns >= p.min_returns;  // -1: not recorded, counted visible
  const double range = std::hypot(o.x - s.robot_world.x, o.y - s.robot_world.y);
  t.scored = visible && range <= p.range_m && object_size(o) <= p.max_object_size_m;
  return t;
}

// Every object of a snapshot as scored (true_object), in its order.
std::vector<TrueObject> true_objects(const Snapshot& s, const PerceptionParams& p) {
  std::vector<TrueObject> objects;
  for (size_t i = 0; i < s.obstacles.size(); ++i) objects.push_back(true_object(s, i, p));
  return objects;
}

// Scored matches of one frame: track id -> index of the true object.
using FrameMatches = std::map<int64_t, size_t>;

}  // namespace

namespace {

struct TrackingPass {
  std::map<int64_t, FrameMatches> frames;  // by the obstacle list's utime
  std::map<int64_t, int64_t> first_seen;   // track id -> first utime
  int64_t untruthful = 0;
};

TrackingPass run_tracking(const Decoded& d, const Timeline& tl, const PerceptionParams& p, ClearMot* mot) {
  TrackingPass pass;
  const int64_t t0 = d.truth.front().utime;
  for (size_t f = 0; f < d.lists.size(); ++f) {
    const evade::obstacle_list_t& l = d.lists[f];
    for (const auto& o : l.obstacles) pass.first_seen.emplace(o.id, l.utime);
    Snapshot s;
    if (!tl.at(l.utime, &s)) {
      ++pass.untruthful;
      continue;
    }
    const std::vector<TrueObject> objects = true_objects(s, p);
    std::vector<Hypothesis> hyps;
    for (const auto& o : l.obstacles)
      hyps.push_back({o.id, {o.x, o.y}, std::hypot(o.x - s.robot_odom.x, o.y - s.robot_odom.y) <= p.range_m});
    const int64_t next = f + 1 < d.lists.size() ? d.lists[f + 1].utime : l.utime;
    const int64_t prev = f > 0 ? d.lists[f - 1].utime : l.utime;
    const double dt_s = (next > l.utime ? next - l.utime : l.utime - prev) * 1e-6;
    const std::map<int, int64_t> matches = mot->add_frame((l.utime - t0) * 1e-6, dt_s, objects, hyps);
    FrameMatches& fm = pass.frames[l.utime];
    for (size_t i = 0; i < objects.size(); ++i) {
      auto m = matches.find(objects[i].id);
      if (objects[i].scored && m != matches.end()) fm[m->second] = i;
    }
  }
  return pass;
}

struct Displacement {
  double ade_sum = 0.0, fde_sum = 0.0;
  int64_t n = 0;
  std::optional<double> ade() const { return n ? std::optional<double>(ade_sum / n) : std::nullopt; }
  std::optional<double> fde() const { return n ? std::optional<double>(fde_sum / n) : std::nullopt; }
};

// Errors of one track's predicted centres against the truth; false when
// the truth ends before the horizon does.
bool score_track(const evade::prediction_list_t& list, const evade::track_prediction_t& tp, size_t object,
                 const Timeline& tl, const PerceptionParams& p, std::vector<double>* errors, std::vector<bool>* inside,
                 std::vector<double>* area, std::vector<TrueObject>* bodies) {
  for (int k = 0; k < tp.horizon; ++k) {
    Snapshot s;
    if (!tl.at(list.utime + std::llround(k * list.dt * 1e6), &s) || object >= s.obstacles.size()) return false;
    bodies->push_back(true_object(s, object, p));
    const Vec2 truth = s.to_odom({s.obstacles[object].x, s.obstacles[object].y});
    const double dx = truth.x - tp.x[k], dy = truth.y - tp.y[k];
    const double c = std::cos(tp.theta[k]), sn = std::sin(tp.theta[k]);
    const double u = (c * dx + sn * dy) / tp.a[k], v = (-sn * dx + c * dy) / tp.b[k];
    errors->push_back(std::hypot(dx, dy));
    inside->push_back(u * u + v * v <= 1.0);
    area->push_back(M_PI * tp.a[k] * tp.b[k]);
  }
  return true;
}

void add_displacement(const std::vector<double>& err, double dt, double horizon_s, Displacement* d) {
  const int k = static_cast<int>(std::lround(horizon_s / dt));
  if (k < 1 || k >= static_cast<int>(err.size())) return;
  double sum = 0.0;
  for (int i = 1; i <= k; ++i) sum += err[static_cast<size_t>(i)];
  d->ade_sum += sum / k;
  d->fde_sum += err[static_cast<size_t>(k)];
  ++d->n;
}

// Sums for the walkers' error decomposition (PerceptionMetrics).
struct WalkerSources {
  double centre = 0.0, radial = 0.0, velocity = 0.0, cv_truth = 0.0;
  int64_t n = 0, n_cv = 0;
  std::optional<double> mean(double sum, int64_t count) const {
    return count ? std::optional<double>(sum / count) : std::nullopt;
  }
};

// One walker prediction's step-0 centre and velocity errors, and the 1 s ADE
// of extrapolating its true centre and velocity at constant velocity.
void add_walker_sources(const evade::prediction_list_t& list, const evade::track_prediction_t& tp, size_t object,
                        const Snapshot& now, const Timeline& tl, WalkerSources* w) {
  const auto& o = now.obstacles[object];
  const Vec2 c = now.to_odom({o.x, o.y});
  const Vec2 robot = now.to_odom({now.robot_world.x, now.robot_world.y});
  const double rot = now.robot_odom.yaw - now.robot_world.yaw;
  const double vx = std::cos(rot) * o.vx - std::sin(rot) * o.vy, vy = std::sin(rot) * o.vx + std::cos(rot) * o.vy;
  const double dx = tp.x[0] - c.x, dy = tp.y[0] - c.y;
  const double range = std::hypot(c.x - robot.x, c.y - robot.y);
  w->centre += std::hypot(dx, dy);
  if (range > 1e-9) w->radial += (dx * (c.x - robot.x) + dy * (c.y - robot.y)) / range;
  w->velocity += std::hypot(tp.vx - vx, tp.vy - vy);
  ++w->n;
  const int k1 = static_cast<int>(std::lround(1.0 / list.dt));
  double sum = 0.0;
  for (int k = 1; k <= k1; ++k) {
    Snapshot s;
    if (!tl.at(list.utime + std::llround(k * list.dt * 1e6), &s) || object >= s.obstacles.size()) return;
    const Vec2 truth = s.to_odom({s.obstacles[object].x, s.obstacles[object].y});
    sum += std::hypot(c.x + vx * k * list.dt - truth.x, c.y + vy * k * list.dt - truth.y);
  }
  w->cv_truth += sum / k1;
  ++w->n_cv;
}

bool is_walker(const evade::sim_obstacle_t& o, const PerceptionParams& p) {
  return o.shape == "cylinder" && o.radius <= p.walker_max_radius_m && std::hypot(o.vx, o.vy) <= p.walker_max_speed_mps;
}

// Static structure published as moving (PerceptionMetrics::static_*).
struct StaticMotion {
  int64_t frames = 0, moving = 0;
  double speed_sum = 0.0;
  std::set<int64_t> moving_ids;
};

// Object i has stood still for the last second: no velocity now, and the
// same place and no velocity a second earlier (when the truth goes back so far).
bool still(const Snapshot& now, const Snapshot* before, size_t i) {
  const auto& o = now.obstacles[i];
  if (o.vx != 0.0 || o.vy != 0.0) return false;
  if (!before || i >= before->obstacles.size()) return true;
  const auto& b = before->obstacles[i];
  return b.vx == 0.0 && b.vy == 0.0 && b.x == o.x && b.y == o.y;
}

// One prediction list's tracks within range_m whose centre lies within
// match_gate_m of a still object's shape and farther than that from every
// moving one; their published speed.
void add_static_motion(const evade::prediction_list_t& list, const Snapshot& now, const Timeline& tl,
                       const PerceptionParams& p, StaticMotion* s) {
  Snapshot before;
  const bool has_before = tl.at(list.utime - 1000000, &before);
  const std::vector<TrueObject> objects = true_objects(now, p);
  std::vector<bool> is_still;
  for (size_t i = 0; i < now.obstacles.size(); ++i) is_still.push_back(still(now, has_before ? &before : nullptr, i));
  for (const auto& tp : list.tracks) {
    if (tp.horizon < 1) continue;
    const Vec2 c{tp.x[0], tp.y[0]};
    if (std::hypot(c.x - now.robot_odom.x, c.y - now.robot_odom.y) > p.range_m) continue;
    double d_still = 1e300, d_moving = 1e300;
    for (size_t i = 0; i < objects.size(); ++i) {
      double& d = is_still[i] ? d_still : d_moving;
      d = std::min(d, objects[i].distance_to(c));
    }
    if (d_still > p.match_gate_m || d_moving <= p.match_gate_m) continue;
    const double v = std::hypot(tp.vx, tp.vy);
    ++s->frames;
    s->speed_sum += v;
    if (v <= p.static_max_speed_mps) continue;
    ++s->moving;
    s->moving_ids.insert(tp.id);
  }
}

}  // namespace

PerceptionMetrics compute_perception(const std::vector<bus::LogEvent>& events, const PerceptionParams& p,
                                     const std::string& obstacles_channel, const std::string& predictions_channel) {
  Decoded d = decode(events, obstacles_channel, predictions_channel);
  Timeline tl(d.truth, d.odom);
  ClearMot mot(p.match_gate_m);
  const TrackingPass pass = run_tracking(d, tl, p, &mot);
  PerceptionMetrics m;
  m.mot = mot.totals();
  m.untruthful_frames = pass.untruthful;
  Displacement d1, d25, walker1;
  WalkerSources sources;
  StaticMotion static_motion;
  for (const auto& list : d.predictions) {
    auto frame = pass.frames.find(list.utime);
    if (frame == pass.frames.end()) continue;
    Snapshot now;
    if (!tl.at(list.utime, &now)) continue;
    add_static_motion(list, now, tl, p, &static_motion);
    Snapshot before;
    const bool has_before = tl.at(list.utime - 1000000, &before);
    if (m.dt_s == 0.0) m.dt_s = list.dt;
    for (const auto& tp : list.tracks) {
      auto match = frame->second.find(tp.id);
      if (match == frame->second.end() || tp.horizon < 1) continue;
      std::vector<double> err, area;
      std::vector<bool> inside;
      std::vector<TrueObject> bodies;
      if (!score_track(list, tp, match->second, tl, p, &err, &inside, &area, &bodies)) continue;
      const auto seen = pass.first_seen.find(tp.id);
      const double age_s = seen != pass.first_seen.end() ? (list.utime - seen->second) * 1e-6 : 0.0;
      const bool old = age_s >= p.min_track_age_s;
      const size_t i = match->second;
      add_calibration(tp, bodies, classify(now.obstacles[i], still(now, has_before ? &before : nullptr, i)), age_s,
                      p.min_track_age_s, &m.ellipses);
      if (m.steps.size() < err.size()) m.steps.resize(err.size());
      for (size_t k = 0; k < err.size(); ++k) {
        StepScore& st = m.steps[k];
        ++st.n_all;
        st.inside_all += inside[k];
        st.error_sum_m += err[k];
        st.area_sum_m2 += area[k];
        if (old) {
          ++st.n;
          st.inside += inside[k];
        }
      }
      ++m.predictions;
      add_displacement(err, list.dt, 1.0, &d1);
      add_displacement(err, list.dt, 2.5, &d25);
      if (!is_walker(now.obstacles[match->second], p)) continue;
      add_displacement(err, list.dt, 1.0, &walker1);
      add_walker_sources(list, tp, match->second, now, tl, &sources);
    }
  }
  m.ade_1s_m = d1.ade();
  m.fde_1s_m = d1.fde();
  m.ade_2_5s_m = d25.ade();
  m.fde_2_5s_m = d25.fde();
  m.walker_ade_1s_m = walker1.ade();
  m.walker_predictions = walker1.n;
  m.walker_centre_error_m = sources.mean(sources.centre, sources.n);
  m.walker_centre_radial_m = sources.mean(sources.radial, sources.n);
  m.walker_velocity_error_mps = sources.mean(sources.velocity, sources.n);
  m.walker_ade_1s_cv_truth_m = sources.mean(sources.cv_truth, sources.n_cv);
  m.static_track_frames = static_motion.frames;
  m.static_moving_frames = static_motion.moving;
  m.static_moving_tracks = int64_t(static_motion.moving_ids.size());
  m.static_speed_sum_mps = static_motion.speed_sum;
  return m;
}

namespace {

std::string num(std::optional<double> v) {
  if (!v || !std::isfinite(*v)) return "null";
  std::ostringstream s;
  s.precision(6);
  s << *v;
  return s.str();
}

template <typename F>
std::string array(const std::vector<StepScore>& steps, F f) {
  std::string out = "[";
  for (size_t k = 0; k < steps.size(); ++k) out += (k ? ", " : "") + f(steps[k]);
  return out + "]";
}

std::string ratio(int64_t a, int64_t b) { return b ? num(double(a) / double(b)) : "null"; }

}  // namespace

std::string perception_json(const PerceptionMetrics& m, const PerceptionParams& p) {
  const MotTotals& t = m.mot;
  double ttt_sum = 0.0, ttt_max = 0.0;
  for (double v : t.time_to_track_s) {
    ttt_sum += v;
    ttt_max = std::max(ttt_max, v);
  }
  // Coverage of the calibrated tracks over the first 2.5 s (the worst step).
  std::optional<double> coverage_min;
  for (size_t k = 1; k < m.steps.size() && k * m.dt_s <= 2.5 + 1e-9; ++k)
    if (m.steps[k].n) coverage_min = std::min(coverage_min.value_or(1.0), double(m.steps[k].inside) / m.steps[k].n);
  std::ostringstream o;
  o << "{\n  \"frames\": " << t.frames << ",\n  \"objects\": " << t.objects << ",\n  \"matches\": " << t.matches
    << ",\n  \"misses\": " << t.misses << ",\n  \"false_positives\": " << t.false_positives
    << ",\n  \"splits\": " << t.splits << ",\n  \"merges\": " << t.merges << ",\n  \"id_switches\": " << t.id_switches
    << ",\n  \"fragmentations\": " << t.fragmentations << ",\n  \"mota\": " << num(t.mota())
    << ",\n  \"motp_m\": " << num(t.motp_m()) << ",\n  \"track_s\": " << num(t.track_s)
    << ",\n  \"id_switches_per_100_track_s\": "
    << num(t.track_s > 0 ? std::optional<double>(100.0 * t.id_switches / t.track_s) : std::nullopt)
    << ",\n  \"mostly_tracked\": " << t.mostly_tracked << ",\n  \"partially_tracked\": " << t.partially_tracked
    << ",\n  \"mostly_lost\": " << t.mostly_lost << ",\n  \"never_tracked\": " << t.never_tracked
    << ",\n  \"time_to_track_s_mean\": "
    << num(t.time_to_track_s.empty() ? std::nullopt : std::optional<double>(ttt_sum / t.time_to_track_s.size()))
    << ",\n  \"time_to_track_s_max\": "
    << num(t.time_to_track_s.empty() ? std::nullopt : std::optional<double>(ttt_max))
    << ",\n  \"untruthful_frames\": " << m.untruthful_frames << ",\n  \"predictions\": " << m.predictions
    << ",\n  \"ade_1s_m\": " << num(m.ade_1s_m) << ",\n  \"fde_1s_m\": " << num(m.fde_1s_m)
    << ",\n  \"ade_2_5s_m\": " << num(m.ade_2_5s_m) << ",\n  \"fde_2_5s_m\": " << num(m.fde_2_5s_m)
    << ",\n  \"walker_ade_1s_m\": " << num(m.walker_ade_1s_m) << ",\n  \"walker_predictions\": " << m.walker_predictions
    << ",\n  \"walker_centre_error_m\": " << num(m.walker_centre_error_m)
    << ",\n  \"walker_centre_radial_m\": " << num(m.walker_centre_radial_m)
    << ",\n  \"walker_velocity_error_mps\": " << num(m.walker_velocity_error_mps)
    << ",\n  \"walker_ade_1s_cv_truth_m\": " << num(m.walker_ade_1s_cv_truth_m)
    << ",\n  \"static_track_frames\": " << m.static_track_frames
    << ",\n  \"static_moving_frames\": " << m.static_moving_frames
    << ",\n  \"static_moving_fraction\": " << ratio(m.static_moving_frames, m.static_track_frames)
    << ",\n  \"static_speed_mean_mps\": "
    << (m.static_track_frames ? num(m.static_speed_sum_mps / double(m.static_track_frames)) : std::string("null"))
    << ",\n  \"static_moving_tracks\": " << m.static_moving_tracks << ",\n  \"step_dt_s\": " << num(m.dt_s)
    << ",\n  \"coverage\": " << array(m.steps, [](const StepScore& s) { return ratio(s.inside, s.n); })
    << ",\n  \"coverage_n\": " << array(m.steps, [](const StepScore& s) { return std::to_string(s.n); })
    << ",\n  \"coverage_inside\": " << array(m.steps, [](const StepScore& s) { return std::to_string(s.inside); })
    << ",\n  \"coverage_all\": " << array(m.steps, [](const StepScore& s) { return ratio(s.inside_all, s.n_all); })
    << ",\n  \"coverage_min_2_5s\": " << num(coverage_min) << ",\n  \"mean_error_m\": "
    << array(m.steps, [](const StepScore& s) { return s.n_all ? num(s.error_sum_m / s.n_all) : std::string("null"); })
    << ",\n  \"ellipse_area_m2\": "
    << array(m.steps, [](const StepScore& s) { return s.n_all ? num(s.area_sum_m2 / s.n_all) : std::string("null"); })
    << ",\n"
    << calibration_json(m.ellipses) << ",\n  \"params\": {\"range_m\": " << num(p.range_m)
    << ", \"min_returns\": " << p.min_returns << ", \"match_gate_m\": " << num(p.match_gate_m)
    << ", \"max_object_size_m\": " << num(p.max_object_size_m) << ", \"min_track_age_s\": " << num(p.min_track_age_s)
    << ", \"static_max_speed_mps\": " << num(p.static_max_speed_mps) << "}\n}\n";
  return o.str();
}

const char* perception_rules() {
  return R"(Perception metrics (lib/metrics/perception_metrics.h, clear_mot.h), from one run log:
- Frames: every OBSTACLES message. The truth at its utime is SIM_TRUTH interpolated
  linearly between the samples around it, carried into the odometry frame through the
  robot's true and odometry poses at that time (odometry drift does not count as error).
- Scored objects: within range_m of the robot (centre), visible (at least min_returns
  LiDAR returns in the sensor's last complete revolution, SIM_TRUTH lidar_returns; -1,
  not recorded, counts as visible), and no larger than max_object_size_m (walls are not
  one object). Tracks farther than range_m from the robot are never false positives.
- Matching (CLEAR MOT): an object keeps last frame's track while that is within
  match_gate_m of its shape; the rest are matched nearest first within the gate.
  mota = 1 - (misses + false_positives + id_switches) / objects (object-frames);
  motp_m = mean centre distance of the matches; an identity switch: a scored object
  matched to another track than its previous one; a fragmentation: tracked, missed,
  tracked again; a track unmatched near an unscored object is no false positive;
  splits: false positives within the gate of a scored object another track matched
  (one object seen as several clusters); merges: misses with a track within the gate
  that matched another object (two objects seen as one).
  mostly_tracked / mostly_lost: matched in >= 80 % / <= 20 % of its scored frames;
  time_to_track_s: first scored frame to first match. track_s: scored matches times
  the frame period; id_switches_per_100_track_s = 100 * id_switches / track_s.
- Predictions: every track of an OBSTACLE_PREDICTIONS list whose utime is a frame's and
  whose track was matched to a scored object there. Step k is compared with the
  object's true centre at utime + k * dt. ade_Ts_m: mean over predictions of the mean
  error over steps 1..T/dt; fde_Ts_m: the error at step T/dt (T = 1 s, 2.5 s);
  walker_ade_1s_m: the same for cylinders no wider than walker_max_radius_m moving no
  faster than walker_max_speed_mps. Where the walkers' error comes from, over the same
  predictions: walker_centre_error_m (step 0), walker_centre_radial_m (its component
  along robot -> walker; negative: towards the robot), walker_velocity_error_mps (the
  published velocity against the true one), walker_ade_1s_cv_truth_m (the 1 s ADE of the
  true centre extrapolated at the true velocity: what scripted turns cost).
- Calibration: coverage[k] = fraction of true centres inside the published (inflated)
  ellipse at step k, over tracks at least min_track_age_s old (first OBSTACLES
  appearance); coverage_all: every track; coverage_min_2_5s: the worst step in
  (0, 2.5 s]; ellipse_area_m2[k]: mean pi * a * b.
- The ellipses' size (ellipse_calibration.h), per step, by object class (class_*: tracks
  at least min_track_age_s old; walker, bike, ball, dog, static: still for the last
  second, other) and by track age (age_*: 0-0.5, 0.5-1, 1-2, 2-5, 5+ s, every track):
  *_n, *_coverage (centre inside), *_inflation_coverage (centre error <= sigma: the
  inflation alone covers it), *_body_coverage (the whole true body inside: a disc, a
  box's corners), *_area_m2, *_inflation_m (mean sigma), *_error_m (mean centre error);
  *_extent_excess_m: step 0's
  sqrt((a - sigma)(b - sigma)) less the body's radius (a box: sqrt(length width) / 2).
- Static structure's false motion: every track of every OBSTACLE_PREDICTIONS list
  (step 0) within range_m of the robot whose centre lies within match_gate_m of the
  shape of an object that has stood still for the last second (no velocity now, and
  the same place and no velocity 1 s earlier), walls included, and farther than
  match_gate_m from every other object: static_track_frames. static_moving_frames:
  those published faster than static_max_speed_mps (static_moving_fraction their
  share, static_moving_tracks their distinct ids); static_speed_mean_mps: the mean
  published speed over all of them.
)";
}

}  // namespace evade::metrics
