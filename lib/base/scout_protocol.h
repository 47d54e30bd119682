// AgileX Scout 2.0 UART protocol, version 1 (RS-232, 115200 8N1): frames,
// encoders and decoders for both directions, and a byte-stream parser.
//
// Used by base_driver (encodes commands, decodes status) and by the
// simulator (decodes commands, encodes status), so every frame kind has an
// encoder AND a decoder, and the message structs hold the raw wire integers
// (exact round trip); conversions to SI units are separate functions whose
// rounding is documented next to them.
//
// Frame layout, always 13 bytes:
//
//   byte  0  1  2        3     4   5..10     11     12
//         5A A5 0A       type  id  payload   count  checksum
//                        55 = command (host -> base)
//                        AA = status  (base -> host)
//
//   length (byte 2) is 0x0A, the number of bytes after it minus the checksum;
//   count is a rolling frame counter (wraps 255 -> 0), chosen by the sender;
//   checksum = (sum of bytes 0..11) & 0xFF.
//
// Multi-byte integers are big-endian. Frame ids:
//   command 01 motion: [control mode (02 = serial), fault-clear flag,
//                       int8 linear % of 1.5 m/s, int8 angular % of 0.5235 rad/s, 0, 0]
//   command 02 lights: [control enable, front mode, front custom %, rear mode, rear custom %, 0]
//   status  01 system: [base state, control mode, battery uint16 (0.1 V), fault code uint16]
//   status  02 motion: [linear int16 (mm/s), angular int16 (mrad/s), 0, 0]
//   status  03..06 motor 1..4: [current uint16 (0.1 A), speed int16 (rpm), temperature int8 (degC), 0]
//   status  07 lights: same payload as command 02
//
// Example (exact bytes): motion command, 0.75 m/s (50 %), -0.2618 rad/s
// (-50 %), count 0:  5A A5 0A 55 01 02 00 32 CE 00 00 00 61
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace evade::base {

// ---------------------------------------------------------------- frame ----
inline constexpr size_t kFrameSize = 13;
inline constexpr size_t kPayloadSize = 6;
inline constexpr uint8_t kSof0 = 0x5A;
inline constexpr uint8_t kSof1 = 0xA5;
inline constexpr uint8_t kFrameLength = 0x0A;
inline constexpr uint8_t kTypeCommand = 0x55;
inline constexpr uint8_t kTypeStatus = 0xAA;

// Frame ids (byte 4). Command and status ids live in separate spaces.
inline constexpr uint8_t kIdMotionCommand = 0x01;
inline constexpr uint8_t kIdLightCommand = 0x02;
inline constexpr uint8_t kIdSystemStatus = 0x01;
inline constexpr uint8_t kIdMotionStatus = 0x02;
inline constexpr uint8_t kIdMotor1Status = 0x03;  // motors 1..4 are ids 03..06
inline constexpr uint8_t kIdLightStatus = 0x07;
inline constexpr int kMotorCount = 4;

// Control mode byte (motion command byte 0, system status byte 1).
inline constexpr uint8_t kControlModeStandby = 0x00;
inline constexpr uint8_t kControlModeCan = 0x01;
inline constexpr uint8_t kControlModeSerial = 0x02;
inline constexpr uint8_t kControlModeRemote = 0x03;

// Full-scale speeds of the percent fields of the motion command.
inline constexpr double kMaxLinearMps = 1.5;
inline constexpr double kMaxAngularRadps = 0.5235;

using FrameBytes = std::array<uint8_t, kFrameSize>;

// One frame, without its constant header, length and checksum.
struct Frame {
  uint8_t type = kTypeCommand;  // kTypeCommand or kTypeStatus
  uint8_t id = 0;
  std::array<uint8_t, kPayloadSize> payload{};
  uint8_t count = 0;  // rolling counter
};

// Checksum of the first 12 bytes of a frame: their sum & 0xFF.
uint8_t checksum(const uint8_t* first12);
// The 13 wire bytes of a frame (header, length, checksum filled in).
FrameBytes serialize(const Frame& frame);
// Checks header, length and checksum of 13 bytes; false if any is wrong.
bool deserialize(const uint8_t* bytes13, Frame* out);

// ------------------------------------------------------------- messages ----
// Each message has
//   Frame to_frame(const Msg&, uint8_t count)   (type and id set)
//   bool from_frame(const Frame&, Msg*)         (false: wrong type or id)
// and FrameBytes encode(const Msg&, uint8_t count) = serialize(to_frame(...)).

// Command 01. Velocities in percent of kMaxLinearMps / kMaxAngularRadps.
struct MotionCommand {
  uint8_t control_mode = kControlModeSerial;
  bool clear_fault = false;  // byte 1: 0 or 1 (any non-zero decodes as true)
  int8_t linear_percent = 0;
  int8_t angular_percent = 0;
};

// Command 02 / status 07.
struct LightState {
  bool control_enabled = false;  // command: host takes over the lights
  uint8_t front_mode = 0;        // 0 constant off, 1 constant on, 2 breath, 3 custom
  uint8_t front_custom_percent = 0;
  uint8_t rear_mode = 0;
  uint8_t rear_custom_percent = 0;
};
using LightCommand = LightState;

// Status 01.
struct SystemStatus {
  uint8_t base_state = 0;  // 0 normal, 1 emergency stop, 2 exception
  uint8_t control_mode = kControlModeStandby;
  uint16_t battery_decivolts = 0;  // 0.1 V
  uint16_t fault_code = 0;         // bit field
};

// Status 02.
struct MotionStatus {
  int16_t linear_mm_s = 0;
  int16_t angular_mrad_s = 0;
};

// Status 03..06.
struct MotorStatus {
  int motor = 1;                  // 1..4, id = 0x02 + motor
  uint16_t current_deciamps = 0;  // 0.1 A
  int16_t rpm = 0;
  int8_t temperature_c = 0;
};

Frame to_frame(const MotionCommand& msg, uint8_t count);
Frame to_frame(const SystemStatus& msg, uint8_t count);
Frame to_frame(const MotionStatus& msg, uint8_t count);
Frame to_frame(const MotorStatus& msg, uint8_t count);  // motor outside 1..4 -> clamped
// Lights: the same payload travels both ways, so the direction is explicit.
Frame light_command_frame(const LightState& msg, uint8_t count);
Frame light_status_frame(const LightState& msg, uint8_t count);

bool from_frame(const Frame& frame, MotionCommand* out);
bool from_frame(const Frame& frame, SystemStatus* out);
bool from_frame(const Frame& frame, MotionStatus* out);
bool from_frame(const Frame& frame, MotorStatus* out);
bool light_command_from_frame(const Frame& frame, LightState* out);
bool light_status_from_frame(const Frame& frame, LightState* out);

template <class Msg>
FrameBytes encode(const Msg& msg, uint8_t count) {
  return serialize(to_frame(msg, count));
}

// ------------------------------------------------------ unit conversions ----
// Velocity -> percent: round to nearest (halves away from zero, std::lround)
// of 100 * v / full_scale, then clamp to [-100, 100]. NaN maps to 0.
// E.g. 0.75 m/s -> 50, 0.0074 m/s -> 0 (0.49 %), 0.008 m/s -> 1 (0.53 %),
// -0.008 m/s -> -1, 2.0 m/s -> 100 (clamped), -0.2618 rad/s -> -50.
int8_t linear_percent(double v_mps);
int8_t angular_percent(double omega_radps);
// Percent -> velocity (exact: percent / 100 * full scale).
double linear_from_percent(int8_t percent);
double angular_from_percent(int8_t percent);

// Motion status units: mm/s and mrad/s, round to nearest, clamp to int16.
int16_t linear_mm_s(double v_mps);
int16_t angular_mrad_s(double omega_radps);
inline double linear_mps(const MotionStatus& s) { return s.linear_mm_s * 1e-3; }
inline double angular_radps(const MotionStatus& s) { return s.angular_mrad_s * 1e-3; }
// System status: volts <-> 0.1 V (round to nearest, clamp to uint16).
uint16_t battery_decivolts(double volts);
inline double battery_volts(const SystemStatus& s) { return s.battery_decivolts * 0.1; }

// ---------------------------------------------------------------- parser ----
// Turns an arbitrary byte stream (split reads, line noise, a restarted peer)
// into checked frames. Resynchronisation rule: the parser looks for 5A A5;
// a candidate whose length byte is not 0A, or whose checksum is wrong, is
// rejected by dropping only its first byte, so a real frame that begins
// inside a rejected one is still found. Bytes that cannot start a frame are
// counted as noise. A partial frame at the end of a read waits for the next.
struct ParserStats {
  uint64_t frames = 0;        // valid frames delivered
  uint64_t noise_bytes = 0;   // bytes skipped while hunting for 5A A5
  uint64_t bad_length = 0;    // header found, length byte != 0A
  uint64_t bad_checksum = 0;  // header and length fine, checksum wrong
  uint64_t bad_type = 0;      // checksum fine, type neither 55 nor AA
};

class StreamParser {
 public:
  using Handler = std::function<void(const Frame&)>;

  // Feeds bytes; calls `on_frame` for every valid frame, in stream order.
  void feed(const uint8_t* data, size_t size, const Handler& on_frame);
  // Drops any buffered partial frame (e.g. after the link was reopened).
  void reset() { buffered_ = 0; }

  const ParserStats& stats() const { return stats_; }
  size_t buffered() const { return buffered_; }

 private:
  // Consumes complete candidates from buf_[0..buffered_).
  void scan(const Handler& on_frame);
  std::array<uint8_t, kFrameSize> buf_{};
  size_t buffered_ = 0;
  ParserStats stats_;
};

// "5A A5 0A ..." for logs and test messages.
std::string to_hex(const uint8_t* data, size_t size);
inline std::string to_hex(const FrameBytes& b) { return to_hex(b.data(), b.size()); }

}  // namespace evade::base
