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

}  // namespace

void plot_trajectory(const RunMetrics& m, const std::string& png_path) {
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  auto grow = [&](Vec2 p) {
    xmin = std::min(xmin, p.x);
    xmax = std::max(xmax, p.x);
    ymin = std::min(ymin, p.y);
    ymax = std::max(ymax, p.y);
  };
  // Framed on what the robot did; obstacles far from it are clipped.
  for (auto p : m.robot_path) grow(p);
  for (auto p : m.route) grow(p);
  grow(m.goal);
  xmin -= kWorldPadM;
  xmax += kWorldPadM;
  ymin -= kWorldPadM;
  ymax += kWorldPadM;
  double scale = (kWidth - 2 * kMarginPx) / std::max(xmax - xmin, 1.0);
  int height = static_cast<int>((ymax - ymin) * scale) + 2 * kMarginPx + kLegendPx;
  View v{xmin, ymin, scale, height};

  cairo_surface_t* surf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, kWidth, height);
  cairo_t* cr = cairo_create(surf);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);

  // 1 m grid with labels every 5 m (labels outside the plot area).
  cairo_set_line_width(cr, 0.5);
  cairo_set_font_size(cr, 11);
  for (double x = std::ceil(xmin); x <= xmax; x += 1.0) {
    cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
    cairo_move_to(cr, v.px(x), v.py(ymin));
    cairo_line_to(cr, v.px(x), v.py(ymax));
    cairo_stroke(cr);
    if (std::fmod(std::fabs(x), 5.0) < 1e-9) {
      cairo_set_source_rgb(cr, 0.4, 0.4, 0.4);
      cairo_move_to(cr, v.px(x) - 6, v.py(ymin) + 14);
      cairo_show_text(cr, std::to_string(static_cast<int>(x)).c_str());
    }
  }
  for (double y = std::ceil(ymin); y <= ymax; y += 1.0) {
    cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
    cairo_move_to(cr, v.px(xmin), v.py(y));
    cairo_line_to(cr, v.px(xmax), v.py(y));
    cairo_stroke(cr);
    if (std::fmod(std::fabs(y), 5.0) < 1e-9) {
      cairo_set_source_rgb(cr, 0.4, 0.4, 0.4);
      cairo_move_to(cr, v.px(xmin) - 28, v.py(y) + 4);
      cairo_show_text(cr, std::to_string(static_cast<int>(y)).c_str());
    }
  }

  // Everything in the world is clipped to the plot area.
  cairo_save(cr);
  cairo_rectangle(cr, v.px(xmin), v.py(ymax), (xmax - xmin) * scale, (ymax - ymin) * scale);
  cairo_clip(cr);

  // Route.
  if (m.route.size() >= 2) {
    double dash[] = {8, 6};
    cairo_set_dash(cr, dash, 2, 0);
    cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
    cairo_set_line_width(cr, 1.5);
    cairo_move_to(cr, v.px(m.route[0].x), v.py(m.route[0].y));
    for (auto p : m.route) cairo_line_to(cr, v.px(p.x), v.py(p.y));
    cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0);
  }

  // Obstacles: static ones filled grey; moving ones as their path plus an
  // outline every second and a filled shape at the end.
  for (size_t i = 0; i < m.obstacles.size(); ++i) {
    const auto& o = m.obstacles[i];
    if (o.path.empty()) continue;
    Rgb c = o.dynamic ? kObstacleColours[i % 8] : Rgb{0.45, 0.45, 0.45};
    if (o.dynamic) {
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
          cairo_show_text(cr, (std::to_string(static_cast<int>(std::lround(m.robot_t_s[k]))) + "s").c_str());
        }
      }
    }
    cairo_set_source_rgba(cr, c.r, c.g, c.b, o.dynamic ? 0.5 : 0.8);
    shape_path(cr, v, o, o.path.back(), o.yaw.back());
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_move_to(cr, v.px(o.path.front().x) + 5, v.py(o.path.front().y) - 5);
    cairo_show_text(cr, ("#" + std::to_string(o.id)).c_str());
  }

  // Robot path coloured by speed.
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

  // Time labels on the robot's path, matching the obstacles'.
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  double next_label = kTimeLabelS;
  for (size_t k = 0; k < m.robot_path.size(); ++k) {
    if (m.robot_t_s[k] < next_label) continue;
    next_label += kTimeLabelS;
    cairo_arc(cr, v.px(m.robot_path[k].x), v.py(m.robot_path[k].y), 3, 0, 2 * M_PI);
    cairo_fill(cr);
    cairo_move_to(cr, v.px(m.robot_path[k].x) - 8, v.py(m.robot_path[k].y) - 8);
    cairo_show_text(cr, (std::to_string(static_cast<int>(std::lround(m.robot_t_s[k]))) + "s").c_str());
  }

  // Start, goal.
  if (!m.robot_path.empty()) {
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 1.0);
    rect_path(cr, v, OrientedRect{m.robot_path.front(), m.robot_yaw.front(), m.footprint_length, m.footprint_width});
    cairo_stroke(cr);
  }
  cairo_set_source_rgb(cr, 0.0, 0.6, 0.0);
  cairo_set_line_width(cr, 2.0);
  cairo_arc(cr, v.px(m.goal.x), v.py(m.goal.y), std::max(m.goal_tolerance * scale, 4.0), 0, 2 * M_PI);
  cairo_stroke(cr);

  // Closest approach: footprint and obstacle at that moment, and the gap.
  if (m.closest_sample >= 0) {
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

  cairo_restore(cr);

  // Legend: title, metrics, speed bar.
  double ly = height - kLegendPx + 20;
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
                m.min_dist_m, m.time_to_goal_s ? std::to_string(*m.time_to_goal_s).substr(0, 5).c_str() : "-",
                m.reaction_time_s ? std::to_string(*m.reaction_time_s).substr(0, 5).c_str() : "-",
                m.speed_var ? std::to_string(*m.speed_var).substr(0, 6).c_str() : "-", m.path_length_m,
                m.planner_solve_ms_p50 ? std::to_string(*m.planner_solve_ms_p50).substr(0, 5).c_str() : "-");
  cairo_move_to(cr, kMarginPx, ly + 22);
  cairo_show_text(cr, line);
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
  std::snprintf(line, sizeof line,
                "%.2f m/s   robot speed (path colour); dashed: route; grey: static obstacles; "
                "moving obstacles outlined every second; labels: time since start",
                vmax);
  cairo_move_to(cr, bx + bw - 20, by + bh + 14);
  cairo_show_text(cr, line);

  cairo_destroy(cr);
  cairo_status_t st = cairo_surface_write_to_png(surf, png_path.c_str());
  cairo_surface_destroy(surf);
  if (st != CAIRO_STATUS_SUCCESS) throw std::runtime_error("cannot write " + png_path);
}

}  // namespace evade::metrics
