// evade-viz's controls (keys -> layer switches, camera, pause, step, speed,
// seek) and its timeline over a log. No window: tested alone.
#pragma once

#include <string>
#include <vector>

#include "bus/log.h"
#include "scene.h"
#include "world_state.h"

namespace evade::viz {

// Keys (VTK key symbols; PCL's own keys p w s j c f e q + - g u r l x 0-9
// are left alone):
//   z m t y n b i v   cloud, map, tracks, predictions, plan, route, robot, truth on/off
//   k                 follow the robot with the camera on/off
//   space             pause / play (log)
//   period (.)        one refresh period forward, paused (log)
//   bracketleft/right ([ ]) half / double the playback speed (log)
//   Left / Right      seek back / forward by viz.seek_step_s (log)
//   Home              back to the log's start
struct Controls {
  LayerSwitches layers = all_layers_on();
  bool follow = true;
  bool paused = false;
  double speed = 1.0;
  int steps = 0;           // pending single steps
  double seek_by_s = 0.0;  // pending relative seek
  bool seek_to_start = false;

  // Applies one key press; false when the key is not one of evade-viz's.
  bool on_key(const std::string& keysym, double seek_step_s);
  // "t 12.3 / 35.0 s  x1.0  playing  follow" style status.
  std::string status(double position_s, double duration_s) const;
};

class LogTimeline {
 public:
  // The log's events, sorted by timestamp (stable).
  explicit LogTimeline(std::vector<bus::LogEvent> events);
  double duration_s() const { return duration_s_; }
  double position_s() const { return position_s_; }

  // Rebuilds `w` as it was at t_s seconds into the log (clamped to the
  // log): every ODOMETRY up to then (the pose buffer), then the newest
  // message of every other channel and the last two LIDAR_SCANs (a
  // revolution's first points come from the scan before), in log order.
  void seek(WorldState* w, double t_s);
  // Applies the events after the current position up to position + dt_s.
  void advance(WorldState* w, double dt_s);

 private:
  std::vector<bus::LogEvent> events_;
  size_t next_ = 0;  // first event not applied yet
  int64_t start_utime_ = 0;
  double duration_s_ = 0.0;
  double position_s_ = 0.0;
};

}  // namespace evade::viz
