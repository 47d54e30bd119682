// A small deterministic core used by the bus tests: every ODOMETRY becomes
// a CMD_VEL with twice the velocities, stamped with the input's utime. The
// bus_echo process uses it on ECHO_IN / ECHO_OUT, channels without
// authentication, so that the live tests are about the bus alone
// (auth_test.cpp covers signing).
#pragma once

#include <string>

#include "bus/core.h"
#include "evade/cmd_vel_t.hpp"
#include "evade/odometry_t.hpp"

namespace evade::bus::testing {

class EchoCore : public Core {
 public:
  explicit EchoCore(std::string in = "ODOMETRY", std::string out = "CMD_VEL") : Core("bus_echo"), out_(std::move(out)) {
    subscribe<evade::odometry_t>(in, [this](const evade::odometry_t& m) {
      evade::cmd_vel_t c{};
      c.utime = m.utime;
      c.v = 2.0 * m.v;
      c.omega = 2.0 * m.omega;
      publish(out_, c);
    });
  }

 private:
  std::string out_;
};

}  // namespace evade::bus::testing
