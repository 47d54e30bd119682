#include "scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "metrics/plan_status.h"

namespace evade::viz {

namespace {

constexpr Rgb kRed{1.0f, 0.15f, 0.1f};
constexpr Rgb kOrange{1.0f, 0.6f, 0.0f};
constexpr Rgb kWhite{1.0f, 1.0f, 1.0f};
constexpr Rgb kGreen{0.2f, 1.0f, 0.2f};
constexpr Rgb kCyan{0.0f, 0.9f, 1.0f};
constexpr Rgb kYellow{1.0f, 0.95f, 0.2f};
constexpr float kLineZ = 0.05f;  // lines on the ground drawn just above it

std::vector<WorldPoint> ellipse(double cx, double cy, double a, double b, double theta, int segments, float z) {
  std::vector<WorldPoint> out;
  const double c = std::cos(theta), s = std::sin(theta);
  for (int i = 0; i <= segments; ++i) {
    const double t = 2.0 * M_PI * (i % segments) / segments;
    const double ex = a * std::cos(t), ey = b * std::sin(t);
    out.push_back({float(cx + c * ex - s * ey), float(cy + s * ex + c * ey), z});
  }
  return out;
}

// A rectangle of length x width centred at (x, y), along yaw; closed.
std::vector<WorldPoint> rectangle(double x, double y, double yaw, double length, double width, float z) {
  const double c = std::cos(yaw), s = std::sin(yaw), hl = length / 2, hw = width / 2;
  const double corners[5][2] = {{hl, hw}, {-hl, hw}, {-hl, -hw}, {hl, -hw}, {hl, hw}};
  std::vector<WorldPoint> out;
  for (const auto& k : corners) out.push_back({float(x + c * k[0] - s * k[1]), float(y + s * k[0] + c * k[1]), z});
  return out;
}

// An arrow from (x, y) by (dx, dy): the shaft and a two-stroke head.
std::vector<std::vector<WorldPoint>> arrow(double x, double y, double dx, double dy, float z) {
  const double len = std::hypot(dx, dy);
  const double hx = x + dx, hy = y + dy;
  std::vector<std::vector<WorldPoint>> out = {{{float(x), float(y), z}, {float(hx), float(hy), z}}};
  if (len < 1e-6) return out;
  const double head = std::min(0.25, 0.3 * len), ux = dx / len, uy = dy / len;
  for (double side : {1.0, -1.0}) {
    const double bx = hx - head * (ux * std::cos(0.5) - side * uy * std::sin(0.5));
    const double by = hy - head * (uy * std::cos(0.5) + side * ux * std::sin(0.5));
    out.push_back({{float(hx), float(hy), z}, {float(bx), float(by), z}});
  }
  return out;
}

std::string fmt(const char* f, double a, double b = 0, double c = 0, double d = 0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, f, a, b, c, d);
  return buf;
}

void add_cloud(const WorldState& w, const VizParams& p, Scene* s) {
  PointsPrim pts{kCloud, "cloud", w.cloud, {}, float(p.point_size_px)};
  pts.rgb.reserve(w.cloud.size());
  for (const auto& q : w.cloud) pts.rgb.push_back(height_colour(q.z, p.cloud_min_z_m, p.cloud_max_z_m));
  s->points.push_back(std::move(pts));
}

void add_map(const WorldState& w, const VizParams& p, Scene* s) {
  const auto& m = *w.map;
  PointsPrim cells{kMap, "map_obstacles", {}, {}, float(p.cell_size_px)};
  for (int r = 0; r < m.height && r < int(m.obstacle.size()); ++r)
    for (int c = 0; c < m.width && c < int(m.obstacle[r].size()); ++c) {
      if (!m.obstacle[r][c]) continue;
      const float z = r < int(m.elevation.size()) && c < int(m.elevation[r].size()) && std::isfinite(m.elevation[r][c])
                          ? m.elevation[r][c]
                          : 0.0f;
      cells.xyz.push_back(
          {float(m.origin[0] + (c + 0.5) * m.resolution), float(m.origin[1] + (r + 0.5) * m.resolution), z});
      cells.rgb.push_back(kRed);
    }
  s->points.push_back(std::move(cells));
}

void add_tracks(const WorldState& w, const VizParams& p, Scene* s) {
  std::map<int64_t, std::pair<double, double>> velocity;
  if (w.predictions)
    for (const auto& t : w.predictions->tracks) velocity[t.id] = {t.vx, t.vy};
  LinesPrim shapes{kTracks, "tracks", {}, kOrange, 1.0f, 3.0f};
  LinesPrim arrows{kTracks, "track_velocity", {}, kOrange, 1.0f, 2.0f};
  for (const auto& o : w.obstacles->obstacles) {
    shapes.strips.push_back(ellipse(o.x, o.y, o.a, o.b, o.theta, p.ellipse_segments, kLineZ));
    std::string text = "#" + std::to_string(o.id);
    const auto v = velocity.find(o.id);
    if (v != velocity.end()) {
      const double vx = v->second.first, vy = v->second.second;
      text += fmt(" %.1f m/s", std::hypot(vx, vy));
      for (auto& a : arrow(o.x, o.y, vx * p.velocity_arrow_s, vy * p.velocity_arrow_s, kLineZ))
        arrows.strips.push_back(a);
    }
    s->labels.push_back(
        {kTracks, "track_" + std::to_string(o.id), text, {float(o.x), float(o.y), 0.8f}, kOrange, 0.15f});
  }
  s->lines.push_back(std::move(shapes));
  s->lines.push_back(std::move(arrows));
}

// One polyline set per prediction step, so each step can fade on its own.
void add_predictions(const WorldState& w, const VizParams& p, Scene* s) {
  const auto& pl = *w.predictions;
  const int horizon = pl.horizon;
  for (int k = 1; k < horizon; ++k) {
    const double f = horizon > 2 ? double(k - 1) / (horizon - 2) : 0.0;
    LinesPrim step{
        kPredictions, "prediction_" + std::to_string(k), {}, kYellow, float(1.0 - f * (1.0 - p.prediction_min_opacity)),
        1.0f};
    for (const auto& t : pl.tracks) {
      if (k >= t.horizon || k >= int(t.x.size())) continue;
      step.strips.push_back(ellipse(t.x[k], t.y[k], t.a[k], t.b[k], t.theta[k], p.ellipse_segments, kLineZ));
    }
    if (!step.strips.empty()) s->lines.push_back(std::move(step));
  }
}

void add_plan(const WorldState& w, Scene* s) {
  const auto& pl = *w.plan;
  LinesPrim path{kPlan, "plan", {{}}, plan_colour(pl.status), 1.0f, 4.0f};
  for (size_t i = 0; i < pl.x.size() && i < pl.y.size(); ++i)
    path.strips[0].push_back({float(pl.x[i]), float(pl.y[i]), kLineZ * 2});
  s->lines.push_back(std::move(path));
}

void add_route(const WorldState& w, Scene* s) {
  LinesPrim route{kRoute, "route", {{}}, kWhite, 0.8f, 2.0f};
  for (size_t i = 0; i < w.route->x.size() && i < w.route->y.size(); ++i)
    route.strips[0].push_back({float(w.route->x[i]), float(w.route->y[i]), kLineZ});
  s->lines.push_back(std::move(route));
}

void add_robot(const WorldState& w, const VizParams& p, Scene* s) {
  const auto& o = *w.odometry;
  LinesPrim robot{kRobot, "robot", {}, kGreen, 1.0f, 4.0f};
  robot.strips.push_back(rectangle(o.x, o.y, o.yaw, p.footprint_length_m, p.footprint_width_m, kLineZ));
  const double c = std::cos(o.yaw), sn = std::sin(o.yaw), hl = p.footprint_length_m / 2;
  robot.strips.push_back(
      {{float(o.x), float(o.y), kLineZ}, {float(o.x + c * (hl + 0.2)), float(o.y + sn * (hl + 0.2)), kLineZ}});
  s->lines.push_back(std::move(robot));
}

void add_truth(const WorldState& w, const VizParams& p, Scene* s) {
  const auto& t = *w.truth;
  LinesPrim shapes{kTruth, "truth", {}, kCyan, 1.0f, 2.0f};
  for (const auto& o : t.obstacles) {
    for (float z : {0.0f, float(o.height)}) {
      if (o.shape == "box") {
        shapes.strips.push_back(rectangle(o.x, o.y, o.yaw, o.length, o.width, z));
      } else {
        shapes.strips.push_back(ellipse(o.x, o.y, o.radius, o.radius, 0.0, p.ellipse_segments, z));
      }
    }
  }
  shapes.strips.push_back(rectangle(t.x, t.y, t.yaw, t.footprint_length, t.footprint_width, 0.0f));
  s->lines.push_back(std::move(shapes));
}

void add_hud(const WorldState& w, const LayerSwitches& on, Scene* s) {
  if (w.plan) {
    const auto& pl = *w.plan;
    s->hud.push_back("plan: " + std::string(evade::metrics::plan_status_name(pl.status)) + " (" + pl.mode + ")" +
                     fmt("  solve %.1f ms, %.0f iterations, min h %.2f m", pl.solve_time_us * 1e-3,
                         double(pl.iterations), pl.min_barrier) +
                     (pl.min_barrier >= 1e5 ? " (no obstacle)" : ""));
  } else {
    s->hud.push_back("plan: none yet");
  }
  if (w.odometry)
    s->hud.push_back(fmt("robot: (%.2f, %.2f) m, %.0f deg, %.2f m/s", w.odometry->x, w.odometry->y,
                         w.odometry->yaw * 180.0 / M_PI, w.odometry->v));
  std::string tracks = "tracks: " + std::to_string(w.obstacles ? w.obstacles->obstacles.size() : 0);
  tracks += "  cloud: " + std::to_string(w.cloud.size()) + " points";
  s->hud.push_back(tracks);
  std::string layers = "layers:";
  const char* keys = "zmtynbiv";
  for (int l = 0; l < kNumLayers; ++l)
    layers += std::string(" [") + keys[l] + "]" + layer_name(Layer(l)) + (on[l] ? "" : "(off)");
  s->hud.push_back(layers);
}

}  // namespace

const char* layer_name(Layer l) {
  static const char* names[kNumLayers] = {"cloud", "map", "tracks", "predictions", "plan", "route", "robot", "truth"};
  return names[l];
}

LayerSwitches all_layers_on() {
  LayerSwitches on;
  on.fill(true);
  return on;
}

Rgb height_colour(double z, double min_z, double max_z) {
  const double t = std::clamp((z - min_z) / (max_z - min_z), 0.0, 1.0);
  // blue -> cyan -> green -> yellow -> red, linear between the stops
  const double seg = t * 4.0;
  const int k = std::min(3, int(seg));
  const double f = seg - k;
  static const Rgb stops[5] = {{0, 0, 1}, {0, 1, 1}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}};
  const Rgb a = stops[k], b = stops[k + 1];
  return {float(a.r + (b.r - a.r) * f), float(a.g + (b.g - a.g) * f), float(a.b + (b.b - a.b) * f)};
}

Rgb plan_colour(int8_t status) {
  switch (status) {
    case evade::plan_t::STATUS_OK:
      return {0.1f, 0.9f, 0.3f};
    case evade::plan_t::STATUS_FALLBACK:
      return kOrange;
    case evade::plan_t::STATUS_RECOVERING:
      return {1.0f, 0.2f, 1.0f};
    case evade::plan_t::STATUS_GOAL:
      return {0.3f, 0.5f, 1.0f};
    case evade::plan_t::STATUS_NO_ROUTE:
      return {0.6f, 0.6f, 0.6f};
    default:
      return kRed;  // stopping, stale input
  }
}

Scene build_scene(const WorldState& w, const LayerSwitches& on, const VizParams& p) {
  Scene s;
  if (on[kCloud] && !w.cloud.empty()) add_cloud(w, p, &s);
  if (on[kMap] && w.map) add_map(w, p, &s);
  if (on[kTracks] && w.obstacles) add_tracks(w, p, &s);
  if (on[kPredictions] && w.predictions) add_predictions(w, p, &s);
  if (on[kPlan] && w.plan) add_plan(w, &s);
  if (on[kRoute] && w.route) add_route(w, &s);
  if (on[kRobot] && w.odometry) add_robot(w, p, &s);
  if (on[kTruth] && w.truth) add_truth(w, p, &s);
  if (w.odometry) {
    s.have_robot = true;
    s.robot_x = w.odometry->x;
    s.robot_y = w.odometry->y;
    s.robot_yaw = w.odometry->yaw;
  }
  add_hud(w, on, &s);
  return s;
}

}  // namespace evade::viz
