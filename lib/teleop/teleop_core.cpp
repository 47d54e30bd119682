#include "teleop/teleop_core.h"

#include <algorithm>
#include <cmath>

#include "evade/cmd_vel_t.hpp"
#include "evade/estop_t.hpp"

namespace evade::teleop {
namespace {
int64_t period_us(double hz) { return std::max<int64_t>(1, std::llround(1e6 / hz)); }
}  // namespace

TeleopParams TeleopParams::from_config(const config::Node& root) {
  return config::load<TeleopParams>(root.section("teleop"));
}

TeleopCore::TeleopCore(const TeleopParams& params) : bus::Core("teleop"), params_(params) {
  every(period_us(params.rate_hz), [this] { tick(); });
}

std::unique_ptr<TeleopCore> TeleopCore::from_config(const config::Node& root) {
  return std::make_unique<TeleopCore>(TeleopParams::from_config(root));
}

bool TeleopCore::on_key(char key) {
  switch (key) {
    case 'w':
      v_ += params_.linear_step_mps;
      break;
    case 's':
      v_ -= params_.linear_step_mps;
      break;
    case 'a':
      omega_ += params_.angular_step_radps;
      break;
    case 'd':
      omega_ -= params_.angular_step_radps;
      break;
    case ' ':
    case 'x':
      v_ = omega_ = 0.0;
      break;
    default:
      return false;
  }
  v_ = std::clamp(v_, -params_.max_v_mps, params_.max_v_mps);
  omega_ = std::clamp(omega_, -params_.max_omega_radps, params_.max_omega_radps);
  last_key_ = now();
  send();
  return true;
}

void TeleopCore::tick() {
  if (last_key_ < 0) return;  // nothing pressed yet: silent
  if (now() - last_key_ > std::llround(params_.hold_s * 1e6)) v_ = omega_ = 0.0;
  send();
}

void TeleopCore::stop() {
  v_ = omega_ = 0.0;
  send();
}

void TeleopCore::send() {
  evade::cmd_vel_t m{};
  m.utime = now();
  m.v = v_;
  m.omega = omega_;
  publish("CMD_VEL", m);
}

std::unique_ptr<EstopCore> EstopCore::from_config(const config::Node& root, bool engaged, std::string reason,
                                                  bool hold) {
  return std::make_unique<EstopCore>(TeleopParams::from_config(root), engaged, std::move(reason), hold);
}

EstopCore::EstopCore(const TeleopParams& params, bool engaged, std::string reason, bool hold)
    : bus::Core("estop"), params_(params), engaged_(engaged), reason_(std::move(reason)), hold_(hold) {
  every(period_us(params.estop_rate_hz), [this] {
    if (done()) return;
    evade::estop_t m{};
    m.utime = now();
    m.engaged = engaged_;
    m.reason = reason_;
    publish("ESTOP", m);
    ++sent_;
  });
}

}  // namespace evade::teleop
