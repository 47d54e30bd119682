// Which primitives evade-viz draws for which message: a Scene of point
// sets, polylines, 3D labels and heads-up text, built from a WorldState and
// the layers switched on. No window, no PCL: tested alone; render.h draws it.
//
//   layer        from                   drawn as
//   cloud        LIDAR_POINTS/SCAN      points, coloured by height (blue low .. red high)
//   map          ELEVATION_MAP          obstacle cells: red squares at their elevation
//   tracks       OBSTACLES (+ velocity  each track's ellipse (orange), "#id v m/s" label,
//                from PREDICTIONS)      velocity arrow to where it is in velocity_arrow_s
//   predictions  OBSTACLE_PREDICTIONS   predicted ellipses over the horizon (yellow), fading
//   plan         PLAN                   planned path coloured by status, status in the HUD
//   route        ROUTE                  the reference polyline (white)
//   robot        ODOMETRY               the footprint rectangle and a heading tick (green)
//   truth        SIM_TRUTH              true obstacle outlines (cyan), true robot outline
#pragma once

#include <array>
#include <string>
#include <vector>

#include "world_state.h"

namespace evade::viz {

enum Layer { kCloud, kMap, kTracks, kPredictions, kPlan, kRoute, kRobot, kTruth, kNumLayers };
const char* layer_name(Layer l);
using LayerSwitches = std::array<bool, kNumLayers>;
LayerSwitches all_layers_on();

struct Rgb {
  float r, g, b;  // 0..1
};

struct PointsPrim {
  Layer layer;
  std::string id;
  std::vector<WorldPoint> xyz;
  std::vector<Rgb> rgb;  // one per point
  float size_px;
};

struct LinesPrim {
  Layer layer;
  std::string id;
  std::vector<std::vector<WorldPoint>> strips;  // polylines (closed when first == last)
  Rgb rgb;
  float opacity;
  float width_px;
};

struct LabelPrim {
  Layer layer;
  std::string id;
  std::string text;
  WorldPoint at;
  Rgb rgb;
  float height_m;
};

struct Scene {
  std::vector<PointsPrim> points;
  std::vector<LinesPrim> lines;
  std::vector<LabelPrim> labels;
  std::vector<std::string> hud;  // heads-up lines, top first
  bool have_robot = false;
  double robot_x = 0, robot_y = 0, robot_yaw = 0;  // for the follow camera
};

// Colour of a height on the cloud's scale (clamped).
Rgb height_colour(double z, double min_z, double max_z);
// Plan colour by plan_t status.
Rgb plan_colour(int8_t status);

Scene build_scene(const WorldState& w, const LayerSwitches& on, const VizParams& p);

}  // namespace evade::viz
