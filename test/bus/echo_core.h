// A small deterministic core used by the bus tests: every ODOMETRY becomes
// a CMD_VEL with twice the velocities, stamped with the input's utime.
#pragma once

#include "bus/core.h"
#include "evade/cmd_vel_t.hpp"
#include "evade/odometry_t.hpp"

namespace evade::bus::testing {

class EchoCore : public Core {
 public:
  EchoCore() : Core("bus_echo") {
    subscribe<evade::odometry_t>("ODOMETRY", [this](const evade::odometry_t& m) {
      evade::cmd_vel_t c;
      c.utime = m.utime;
      c.v = 2.0 * m.v;
      c.omega = 2.0 * m.omega;
      publish("CMD_VEL", c);
    });
  }
};

}  // namespace evade::bus::testing
