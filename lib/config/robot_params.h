// The two sections every process shares: `robot:` (the base's size and
// limits) and `lidar:` (the sensor model and its mount), each read whole
// through its field list by every process that needs it. A reader checks
// its own limits after loading (the base driver: what the Scout's UART can
// carry; the planner: no reversing), naming file, line and key.
#pragma once

#include <cmath>
#include <string>

#include "config/fields.h"

namespace evade::config {

struct RobotParams {
  double footprint_length_m = 0.42;  // rectangle centred on the base, along the heading
  double footprint_width_m = 0.31;
  double max_v_mps = 1.0;  // forward speed limit
  double min_v_mps = 0.0;  // below 0: the robot may reverse
  double max_omega_radps = 0.5;
  double max_accel_mps2 = 1.0;
  double max_decel_mps2 = 1.5;
  double max_alpha_radps2 = 3.0;

  template <class V>
  void fields(V& v) {
    v.field("footprint_length_m", footprint_length_m, positive());
    v.field("footprint_width_m", footprint_width_m, positive());
    v.field("max_v_mps", max_v_mps, positive());
    v.field("min_v_mps", min_v_mps, between(-max_v_mps, max_v_mps));
    v.field("max_omega_radps", max_omega_radps, positive());
    v.field("max_accel_mps2", max_accel_mps2, positive());
    v.field("max_decel_mps2", max_decel_mps2, positive());
    v.field("max_alpha_radps2", max_alpha_radps2, positive());
  }
};

struct LidarMountParams {  // sensor pose on the base
  double x_m = 0.0;
  double y_m = 0.0;
  double z_m = 0.5;
  double roll_rad = 0.0;
  double pitch_rad = 0.0;
  double yaw_rad = 0.0;

  template <class V>
  void fields(V& v) {
    v.field("x_m", x_m);
    v.field("y_m", y_m);
    v.field("z_m", z_m);
    v.field("roll_rad", roll_rad, between(-M_PI, M_PI));
    v.field("pitch_rad", pitch_rad, between(-M_PI, M_PI));
    v.field("yaw_rad", yaw_rad, between(-M_PI, M_PI));
  }
};

struct LidarParams {
  std::string model = "vlp16";  // vlp16 | rs_helios
  LidarMountParams mount;

  template <class V>
  void fields(V& v) {
    v.choice("model", model, {"vlp16", "rs_helios"});
    v.section("mount", mount);
  }
};

}  // namespace evade::config
