// Draws a Scene in a pcl::visualization::PCLVisualizer: the thin PCL part of
// evade-viz. Every frame replaces what the last one drew.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "scene.h"
#include "world_state.h"

namespace pcl::visualization {
class PCLVisualizer;
}

namespace evade::viz {

class Renderer {
 public:
  explicit Renderer(const VizParams& p);
  ~Renderer();
  // Key presses (VTK key symbols) go to `on_key`.
  void on_key(std::function<void(const std::string&)> fn);
  // Replaces the drawn scene; the status line goes under the HUD.
  void draw(const Scene& s, const std::string& status);
  // Puts the camera behind and above the robot, looking ahead of it.
  void follow(const Scene& s);
  // Handles window events for up to `ms`; false once the window was closed.
  bool spin(int ms);
  // Renders and writes the window to a PNG; false on failure.
  bool snapshot(const std::string& path);

 private:
  VizParams p_;
  std::unique_ptr<pcl::visualization::PCLVisualizer> v_;
  int hud_lines_ = 0;
};

}  // namespace evade::viz
