#include "metrics/trajectory_plot.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace evade::metrics {
namespace {

constexpr int kWidth = 1400;         // px
constexpr int kMarginPx = 60;        // px around the drawing
constexpr int kLegendPx = 110;       // px below the drawing for text and colour bar
constexpr double kWorldPadM = 5.0;   // m around the robot's path and route: half the local map
constexpr double kTimeLabelS = 5.0;  // s between time labels on the robot and the obstacles
constexpr double kOutlineS = 1.0;    // s between outlines of moving obstacles

struct Rgb {
  double r, g, b;
};

// Speed colour map: blue (slow) -> green -> red (fast).
Rgb speed_colour(double t) {
  t = std::clamp(t, 0.0, 1.0);
  if (t < 0.5) return {0.0, 2 * t, 1.0 - 2 * t};
  return {2 * (t - 0.5), 1.0 - 2 * (t - 0.5), 0.0};
}

// Moving obstacles; none grey (grey marks static ones).
const Rgb kObstacleColours[] = {{0.85, 0.33, 0.10}, {0.49, 0.18, 0.56}, {0.47, 0.67, 0.19}, {0.30, 0.75, 0.93},
                                {0.64, 0.08, 0.18}, {0.93, 0.69, 0.13}, {0.0, 0.45, 0.74},  {0.85, 0.2, 0.6}};

struct View {
  double xmin, ymin, scale;
  int height_px;
  double xmax, ymax;
  double px(double x) const { return kMarginPx + (x - xmin) * scale; }
  double py(double y) const { return kMarginPx + (height_px - 2 * kMarginPx - kLegendPx) - (y - ymin) * scale; }
};

void shape_path(cairo_t* cr, const View& v, const ObstacleTrack& o, Vec2 c, double yaw) {
  if (o.shape == "box") {
    OrientedRect r{c, yaw, o.length, o.width};
    auto k = r.corners();
    cairo_move_to(cr, v.px(k[0].x), v.py(k[0].y));
    for (int i = 1; i < 4; ++i) cairo_line_to(cr, v.px(k[i].x), v.py(k[i].y));
    cairo_close_path(cr);
  } else {
    cairo_new_sub_path(cr);
    cairo_arc(cr, v.px(c.x), v.py(c.y), o.radius * v.scale, 0, 2 * M_PI);
  }
}

void rect_path(cairo_t* cr, const View& v, const OrientedRect& r) {
  auto k = r.corners();
  cairo_move_to(cr, v.px(k[0].x), v.py(k[0].y));
  for (int i = 1; i < 4; ++i) cairo_line_to(cr, v.px(k[i].x), v.py(k[i].y));
  cairo_close_path(cr);
}

// Framed on what the robot did; obstacles far from it are clipped.
View frame_view(const RunMetrics& m) {
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  auto grow = [&](Vec2 p) {
    xmin = std::min(xmin, p.x);
    xmax = std::max(xmax, p.x);
    ymin = std::min(ymin, p.y);
    ymax = std::max(ymax, p.y);
  };
  for (auto p : m.robot_path) grow(p);
  for (auto p : m.route) grow(p);
  grow(m.goal);
  xmin -= kWorldPadM;
  xmax += kWorldPadM;
  ymin -= kWorldPadM;
  ymax += kWorldPadM;
  double scale = (kWidth - 2 * kMarginPx) / std::max(xmax - xmin, 1.0);
  int height = static_cast<int>((ymax - ymin) * scale) + 2 * kMarginPx + kLegendPx;
  return View{xmin, ymin, scale, height, xmax, ymax};
}

std::string seconds_label(double t_s) { return std::to_string(static_cast<int>(std::lround(t_s))) + "s"; }

// 1 m grid with labels every 5 m (labels outside the plot area).
void draw_grid(cairo_t* cr, const View& v) {
  cairo_set_line_width(cr, 0.5);
  cairo_set_font_size(cr, 11);
  for (double x = std::ceil(v.xmin); x <= v.xmax; x += 1.0) {
    cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
    cairo_move_to(cr, v.px(x), v.py(v.ymin));
    cairo_line_to(cr, v.px(x), v.py(v.ymax));
    cairo_stroke(cr);
    if (std::fmod(std::fabs(x), 5.0) < 1e-9) {
      cairo_set_source_rgb(cr, 0.4, 0.4, 0.4);
      cairo_move_to(cr, v.px(x) - 6, v.py(v.ymin) + 14);
      cairo_show_text(cr, std::to_string(static_cast<int>(x)).c_str());
    }
  }
  for (double y = std::ceil(v.ymin); y <= v.ymax; y += 1.0) {
    cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
    cairo_move_to(cr, v.px(v.xmin), v.py(y));
    cairo_line_to(cr, v.px(v.xmax), v.py(y));
    cairo_stroke(cr);
    if (std::fmod(std::fabs(y), 5.0) < 1e-9) {
      cairo_set_source_rgb(cr, 0.4, 0.4, 0.4);
      cairo_move_to(cr, v.px(v.xmin) - 28, v.py(y) + 4);
      cairo_show_text(cr, std::to_string(static_cast<int>(y)).c_str());
    }
  }
}

void draw_route(cairo_t* cr, const View& v, const std::vector<Vec2>& route) {
  if (route.size() < 2) return;
  double dash[] = {8, 6};
  cairo_set_dash(cr, dash, 2, 0);
  cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
  cairo_set_line_width(cr, 1.5);
  cairo_move_to(cr, v.px(route[0].x), v.py(route[0].y));
  for (auto p : route) cairo_line_to(cr, v.px(p.x), v.py(p.y));
  cairo_stroke(cr);
  cairo_set_dash(cr, nullptr, 0, 0);
}

// A moving obstacle's path, an outline every kOutlineS and a time label
// every kTimeLabelS.
void draw_obstacle_motion(cairo_t* cr, const View& v, const RunMetrics& m, const ObstacleTrack& o, Rgb c) {
  cairo_set_source_rgb(cr, c.r, c.g, c.b);
  cairo_set_line_width(cr, 1.5);
  cairo_move_to(cr, v.px(o.path[0].x), v.py(o.path[0].y));
  for (auto p : o.path) cairo_line_to(cr, v.px(p.x), v.py(p.y));
  cairo_stroke(cr);
  cairo_set_line_width(cr, 0.7);
  double next_outline = 0.0, next_label = kTimeLabelS;
  for (size_t k = 0; k < o.path.size() && k < m.robot_t_s.size(); ++k) {
    if (m.robot_t_s[k] >= next_outline) {
      next_outline += kOutlineS;
      shape_path(cr, v, o, o.path[k], o.yaw[k]);
      cairo_stroke(cr);
    }
    if (m.robot_t_s[k] >= next_label) {
      next_label += kTimeLabelS;
      cairo_move_to(cr, v.px(o.path[k].x) + 6, v.py(o.path[k].y) + 4);
      cairo_show_text(cr, seconds_label(m.robot_t_s[k]).c_str());
    }
  }
}

// Obstacles: static ones filled grey; moving ones as their path plus an
// outline every second and a filled shape at the end.
void draw_obstacles(cairo_t* cr, const View& v, const RunMetrics& m) {
  for (size_t i = 0; i < m.obstacles.size(); ++i) {
    const auto& o = m.obstacles[i];
    if (o.path.empty()) continue;
    Rgb c = o.dynamic ? kObstacleColours[i % 8] : Rgb{0.45, 0.45, 0.45};
    if (o.dynamic) draw_obstacle_motion(cr, v, m, o, c);
    cairo_set_source_rgba(cr, c.r, c.g, c.b, o.dynamic ? 0.5 : 0.8);
    shape_path(cr, v, o, o.path.back(), o.yaw.back());
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_move_to(cr, v.px(o.path.front().x) + 5, v.py(o.path.front().y) - 5);
    cairo_show_text(cr, ("#" + std::to_string(o.id)).c_str());
  }
}

// The robot's path coloured by speed (full scale: the returned speed, m/s),
// with time labels matching the obstacles'.
double draw_robot_path(cairo_t* cr, const View& v, const RunMetrics& m) {
  double vmax = 0.1;
  for (double s : m.robot_speed) vmax = std::max(vmax, std::fabs(s));
  cairo_set_line_width(cr, 3.0);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  for (size_t k = 1; k < m.robot_path.size(); ++k) {
    Rgb c = speed_colour(std::fabs(m.robot_speed[k]) / vmax);
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
    cairo_move_to(cr, v.px(m.robot_path[k - 1].x), v.py(m.robot_path[k - 1].y));
    cairo_line_to(cr, v.px(m.robot_path[k].x), v.py(m.robot_path[k].y));
    cairo_stroke(cr);
  }
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  double next_label = kTimeLabelS;
  for (size_t k = 0; k < m.robot_path.size(); ++k) {
    if (m.robot_t_s[k] < next_label) continue;
    next_label += kTimeLabelS;
    cairo_arc(cr, v.px(m.robot_path[k].x), v.py(m.robot_path[k].y), 3, 0, 2 * M_PI);
    cairo_fill(cr);
    cairo_move_to(cr, v.px(m.robot_path[k].x) - 8, v.py(m.robot_path[k].y) - 8);
    cairo_show_text(cr, seconds_label(m.robot_t_s[k]).c_str());
  }
  return vmax;
}

void draw_start_goal(cairo_t* cr, const View& v, const RunMetrics& m) {
  if (!m.robot_path.empty()) {
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 1.0);
    rect_path(cr, v, OrientedRect{m.robot_path.front(), m.robot_yaw.front(), m.footprint_length, m.footprint_width});
    cairo_stroke(cr);
  }
  cairo_set_source_rgb(cr, 0.0, 0.6, 0.0);
  cairo_set_line_width(cr, 2.0);
  cairo_arc(cr, v.px(m.goal.x), v.py(m.goal.y), std::max(m.goal_tolerance * v.scale, 4.0), 0, 2 * M_PI);
  cairo_stroke(cr);
}

// Closest approach: footprint and obstacle at that moment, and the gap.
void draw_closest_approach(cairo_t* cr, const View& v, const RunMetrics& m) {
  if (m.closest_sample < 0) return;
  size_t k = static_cast<size_t>(m.closest_sample);
  cairo_set_source_rgb(cr, 0.85, 0.0, 0.0);
  cairo_set_line_width(cr, 1.5);
  rect_path(cr, v, OrientedRect{m.robot_path[k], m.robot_yaw[k], m.footprint_length, m.footprint_width});
  cairo_stroke(cr);
  for (const auto& o : m.obstacles)
    if (o.id == m.closest_obstacle && k < o.path.size()) {
      shape_path(cr, v, o, o.path[k], o.yaw[k]);
      cairo_stroke(cr);
    }
  cairo_set_line_width(cr, 2.0);
  cairo_move_to(cr, v.px(m.closest_on_robot.x), v.py(m.closest_on_robot.y));
  cairo_line_to(cr, v.px(m.closest_on_obstacle.x), v.py(m.closest_on_obstacle.y));
  cairo_stroke(cr);
  char label[64];
  std::snprintf(label, sizeof label, "closest %.2f m at t=%.1f s", m.min_dist_m, m.robot_t_s[k]);
  cairo_set_font_size(cr, 13);
  cairo_move_to(cr, v.px(m.robot_path[k].x) + 10, v.py(m.robot_path[k].y) + 24);
  cairo_show_text(cr, label);
}

// Everything in the world, clipped to the plot area; returns the speed
// scale of the robot's path (m/s).
double draw_world(cairo_t* cr, const View& v, const RunMetrics& m) {
  cairo_save(cr);
  cairo_rectangle(cr, v.px(v.xmin), v.py(v.ymax), (v.xmax - v.xmin) * v.scale, (v.ymax - v.ymin) * v.scale);
  cairo_clip(cr);
  draw_route(cr, v, m.route);
  draw_obstacles(cr, v, m);
  double vmax = draw_robot_path(cr, v, m);
  draw_start_goal(cr, v, m);
  draw_closest_approach(cr, v, m);
  cairo_restore(cr);
  return vmax;
}

std::string optional_text(const std::optional<double>& x, size_t chars) {
  return x ? std::to_string(*x).substr(0, chars) : "-";
}

// Title and metrics lines of the legend, from baseline y ly (px).
void draw_legend_text(cairo_t* cr, const RunMetrics& m, double ly) {
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_font_size(cr, 15);
  char line[512];
  std::snprintf(line, sizeof line, "%s   mode %s   %s%s", m.scenario.c_str(), m.mode.empty() ? "?" : m.mode.c_str(),
                m.reached_goal ? "goal reached" : "goal NOT reached",
                !m.collided  ? ""
                : m.at_fault ? ", COLLIDED (at fault)"
                             : ", COLLIDED (not at fault)");
  cairo_move_to(cr, kMarginPx, ly);
  cairo_show_text(cr, line);
  cairo_set_font_size(cr, 13);
  std::snprintf(line, sizeof line,
                "min dist %.3f m   time to goal %s s   reaction %s s   speed var %s   path %.2f m   solve p50 %s ms",
                m.min_dist_m, optional_text(m.time_to_goal_s, 5).c_str(), optional_text(m.reaction_time_s, 5).c_str(),
                optional_text(m.speed_var, 6).c_str(), m.path_length_m,
                optional_text(m.planner_solve_ms_p50, 5).c_str());
  cairo_move_to(cr, kMarginPx, ly + 22);
  cairo_show_text(cr, line);
}

// The speed colour bar from 0 to vmax (m/s), from baseline y ly (px).
void draw_speed_bar(cairo_t* cr, double vmax, double ly) {
  double bx = kMarginPx, by = ly + 40, bw = 300, bh = 14;
  for (int i = 0; i < 100; ++i) {
    Rgb c = speed_colour(i / 99.0);
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
    cairo_rectangle(cr, bx + i * bw / 100, by, bw / 100 + 0.5, bh);
    cairo_fill(cr);
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_move_to(cr, bx, by + bh + 14);
  cairo_show_text(cr, "0 m/s");
  char line[512];
  std::snprintf(line, sizeof line,
                "%.2f m/s   robot speed (path colour); dashed: route; grey: static obstacles; "
                "moving obstacles outlined every second; labels: time since start",
                vmax);
  cairo_move_to(cr, bx + bw - 20, by + bh + 14);
  cairo_show_text(cr, line);
}

}  // namespace

void plot_trajectory(const RunMetrics& m, const std::string& png_path) {
  View v = frame_view(m);
  cairo_surface_t* surf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, kWidth, v.height_px);
  cairo_t* cr = cairo_create(surf);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  draw_grid(cr, v);
  double vmax = draw_world(cr, v, m);
  double ly = v.height_px - kLegendPx + 20;
  draw_legend_text(cr, m, ly);
  draw_speed_bar(cr, vmax, ly);
  cairo_destroy(cr);
  cairo_status_t st = cairo_surface_write_to_png(surf, png_path.c_str());
  cairo_surface_destroy(surf);
  if (st != CAIRO_STATUS_SUCCESS) throw std::runtime_error("cannot write " + png_path);
}

}  // namespace evade::metrics
