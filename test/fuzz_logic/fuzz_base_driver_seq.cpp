// Logic fuzzer: the base_driver core over random CMD_VEL sequences, status
// frames (motion, system, noise), link events and stops (sequence.h). Its
// ODOMETRY and BASE_STATUS must stay finite, and no motion frame may ask
// for more than the robot's limits.
#include <cmath>

#include "base/base_driver_core.h"
#include "config/config.h"
#include "messages.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace evade;
  static const base::BaseDriverParams params = base::BaseDriverParams::from_config(
      config::load_robot_config(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml"));
  fuzz::Bytes in(data, size);
  base::BaseDriverCore core(params);
  auto serial = [&](fuzz::Bytes& b, int64_t) {
    const uint8_t kind = b.u8() % 3;
    if (kind == 0) {
      base::FrameBytes f =
          base::encode(base::MotionStatus{static_cast<int16_t>(b.u16()), static_cast<int16_t>(b.u16())}, b.u8());
      core.on_serial_bytes(f.data(), f.size());
    } else if (kind == 1) {
      base::SystemStatus s;
      s.base_state = b.u8() % 4;
      s.control_mode = b.u8() % 4;
      s.battery_decivolts = b.u16();
      s.fault_code = b.u16();
      base::FrameBytes f = base::encode(s, b.u8());
      core.on_serial_bytes(f.data(), f.size());
    } else {
      uint8_t noise[32];
      const size_t n = b.u8() % sizeof noise;
      for (size_t i = 0; i < n; ++i) noise[i] = b.u8();
      core.on_serial_bytes(noise, n);
    }
  };
  fuzz::run_sequence(
      core, {{"CMD_VEL", fuzz::cmd_vel}, {"ESTOP", fuzz::estop}}, in, 64,
      {serial, serial, [&](fuzz::Bytes&, int64_t) { core.on_link_opened(); },
       [&](fuzz::Bytes&, int64_t) { core.on_link_lost("fuzz"); }, [&](fuzz::Bytes&, int64_t) { core.stop(); }});
  const std::vector<uint8_t> tx = core.take_tx();
  base::StreamParser parser;
  parser.feed(tx.data(), tx.size(), [&](const base::Frame& f) {
    base::MotionCommand c;
    if (!base::from_frame(f, &c)) std::abort();  // only motion commands are sent
    if (c.linear_percent > base::linear_percent(params.limits.max_v_mps) ||
        c.linear_percent < base::linear_percent(params.limits.min_v_mps) ||
        std::abs(c.angular_percent) > base::angular_percent(params.limits.max_omega_radps))
      std::abort();
  });
  return 0;
}
