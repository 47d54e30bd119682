#include "benchmark/summary_plot.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace evade::benchmark {
namespace {

constexpr int kPanelW = 480;                                      // px
constexpr int kPanelH = 360;                                      // px
constexpr int kColumns = 3;                                       // panels per row at most
constexpr int kLegendH = 50;                                      // px below the panels
constexpr double kPadL = 56, kPadR = 16, kPadT = 36, kPadB = 64;  // px inside a panel around the axes

struct Panel {
  double x0, y0;  // top-left corner of the panel
  double ax() const { return x0 + kPadL; }
  double aw() const { return kPanelW - kPadL - kPadR; }
  double ay(double rate) const { return y0 + kPadT + (1.0 - rate) * (kPanelH - kPadT - kPadB); }
};

void text(cairo_t* cr, double x, double y, const std::string& s, double size, bool centred) {
  cairo_set_font_size(cr, size);
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  cairo_move_to(cr, centred ? x - e.width / 2 - e.x_bearing : x, y);
  cairo_show_text(cr, s.c_str());
}

void draw_axes(cairo_t* cr, const Panel& p, const std::string& title) {
  cairo_set_source_rgb(cr, 0, 0, 0);
  text(cr, p.x0 + kPanelW / 2.0, p.y0 + 22, title, 15, true);
  cairo_set_line_width(cr, 1.0);
  for (int pct = 0; pct <= 100; pct += 25) {
    double y = p.ay(pct / 100.0);
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, p.ax(), y);
    cairo_line_to(cr, p.ax() + p.aw(), y);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
    text(cr, p.x0 + 8, y + 4, std::to_string(pct) + " %", 11, false);
  }
}

void draw_mode(cairo_t* cr, const Panel& p, const GroupSummary& g, double x) {
  // Wilson interval with caps, success rate as a dot.
  cairo_set_source_rgb(cr, 0.0, 0.3, 0.7);
  cairo_set_line_width(cr, 2.0);
  double lo = p.ay(g.success_ci.lo), hi = p.ay(g.success_ci.hi);
  cairo_move_to(cr, x, lo);
  cairo_line_to(cr, x, hi);
  cairo_move_to(cr, x - 8, lo);
  cairo_line_to(cr, x + 8, lo);
  cairo_move_to(cr, x - 8, hi);
  cairo_line_to(cr, x + 8, hi);
  cairo_stroke(cr);
  cairo_arc(cr, x, p.ay(g.rate(g.successes)), 5, 0, 2 * M_PI);
  cairo_fill(cr);
  // At-fault collision rate: a red cross beside the bar.
  if (g.episodes > 0) {
    double cx = x + 18, cy = p.ay(g.rate(g.at_fault));
    cairo_set_source_rgb(cr, 0.85, 0.0, 0.0);
    cairo_move_to(cr, cx - 5, cy - 5);
    cairo_line_to(cr, cx + 5, cy + 5);
    cairo_move_to(cr, cx - 5, cy + 5);
    cairo_line_to(cr, cx + 5, cy - 5);
    cairo_stroke(cr);
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  double base = p.y0 + kPanelH - kPadB;
  text(cr, x, base + 18, g.mode, 13, true);
  char line[64];
  std::snprintf(line, sizeof line, "%d/%d", g.successes, g.episodes);
  text(cr, x, base + 34, line, 11, true);
  if (g.errors > 0) {
    std::snprintf(line, sizeof line, "+%d errors", g.errors);
    cairo_set_source_rgb(cr, 0.85, 0.0, 0.0);
    text(cr, x, base + 48, line, 11, true);
  }
}

}  // namespace

void plot_summary(const std::vector<GroupSummary>& groups, const std::string& png_path) {
  if (groups.empty()) throw std::runtime_error("plot_summary: no groups");
  std::vector<std::string> families;
  for (const auto& g : groups)
    if (std::find(families.begin(), families.end(), g.family) == families.end()) families.push_back(g.family);
  int cols = std::min<int>(kColumns, static_cast<int>(families.size()));
  int rows = (static_cast<int>(families.size()) + cols - 1) / cols;
  int width = cols * kPanelW, height = rows * kPanelH + kLegendH;

  cairo_surface_t* surf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
  cairo_t* cr = cairo_create(surf);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  for (size_t f = 0; f < families.size(); ++f) {
    Panel p{static_cast<double>((f % cols) * kPanelW), static_cast<double>((f / cols) * kPanelH)};
    std::vector<const GroupSummary*> mine;
    for (const auto& g : groups)
      if (g.family == families[f]) mine.push_back(&g);
    draw_axes(cr, p, families[f] == "all" ? "all families" : families[f]);
    double step = p.aw() / mine.size();
    for (size_t m = 0; m < mine.size(); ++m) draw_mode(cr, p, *mine[m], p.ax() + step * (m + 0.5));
  }
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  text(cr, 12, rows * kPanelH + 30,
       "success rate (dot) with its 95 % Wilson interval (bar) per planner mode; red cross: share of episodes "
       "with a collision at fault; k/n: successes/episodes",
       13, false);
  cairo_destroy(cr);
  cairo_status_t st = cairo_surface_write_to_png(surf, png_path.c_str());
  cairo_surface_destroy(surf);
  if (st != CAIRO_STATUS_SUCCESS) throw std::runtime_error("cannot write " + png_path);
}

}  // namespace evade::benchmark
