// The operator's tools (issue 20): keyboard driving and the e-stop, as
// cores that never touch a socket, a clock or a key. Their mains
// (tools/src/teleop, tools/src/estop) feed key presses in and run them on
// the live bus, which signs what they publish (lib/bus/auth.h): base_driver
// obeys neither unsigned.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "bus/core.h"
#include "config/config.h"
#include "config/fields.h"

namespace evade::teleop {

// The `teleop:` section of the robot configuration.
struct TeleopParams {
  double rate_hz = 20.0;            // CMD_VEL while driving
  double linear_step_mps = 0.1;     // per key press
  double angular_step_radps = 0.2;  // per key press
  double max_v_mps = 0.5;           // the keyboard never asks for more
  double max_omega_radps = 1.0;
  double hold_s = 0.6;          // no key for this long: zero (a held key repeats faster)
  double estop_rate_hz = 10.0;  // ESTOP repeated at this rate
  int estop_repeats = 5;        // this many times (UDP may drop one)

  template <class V>
  void fields(V& v) {
    v.field("rate_hz", rate_hz, config::between(5.0, 100.0));
    v.field("linear_step_mps", linear_step_mps, config::between(0.01, 1.0));
    v.field("angular_step_radps", angular_step_radps, config::between(0.01, 2.0));
    v.field("max_v_mps", max_v_mps, config::between(0.01, 3.0));
    v.field("max_omega_radps", max_omega_radps, config::between(0.01, 6.0));
    v.field("hold_s", hold_s, config::between(0.1, 2.0));
    v.field("estop_rate_hz", estop_rate_hz, config::between(1.0, 100.0));
    v.field("estop_repeats", estop_repeats, config::between(1, 1000));
  }
  // root = the whole configuration; reads `teleop:`.
  static TeleopParams from_config(const config::Node& root);
};

// Keys: w / s faster / slower (backwards below zero), a / d turn left /
// right, space or x: stop. Publishes CMD_VEL {v, omega} at rate_hz,
// stamped with the bus time; zero once no key came for hold_s, and zero
// once more on stop() (the main quitting).
class TeleopCore : public bus::Core {
 public:
  explicit TeleopCore(const TeleopParams& params);
  // The core from the whole configuration (reads `teleop:`).
  static std::unique_ptr<TeleopCore> from_config(const config::Node& root);
  // Inside Core::input: one key press. False for a key it does not know.
  bool on_key(char key);
  void stop();
  double v() const { return v_; }
  double omega() const { return omega_; }

 private:
  void tick();
  void send();
  TeleopParams params_;
  double v_ = 0.0, omega_ = 0.0;
  int64_t last_key_ = -1;
};

// Publishes ESTOP {engaged, reason} estop_repeats times at estop_rate_hz
// from the first bus time (forever with `hold`), then is done().
class EstopCore : public bus::Core {
 public:
  EstopCore(const TeleopParams& params, bool engaged, std::string reason, bool hold);
  // The core from the whole configuration (reads `teleop:`) and the command line's choices.
  static std::unique_ptr<EstopCore> from_config(const config::Node& root, bool engaged, std::string reason, bool hold);
  bool done() const { return !hold_ && sent_ >= params_.estop_repeats; }
  int sent() const { return sent_; }

 private:
  TeleopParams params_;
  bool engaged_;
  std::string reason_;
  bool hold_;
  int sent_ = 0;
};

}  // namespace evade::teleop
