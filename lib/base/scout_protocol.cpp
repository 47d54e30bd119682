#include "base/scout_protocol.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

namespace evade::base {

namespace {

void put_u16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v >> 8);
  p[1] = static_cast<uint8_t>(v & 0xFF);
}
uint16_t get_u16(const uint8_t* p) { return static_cast<uint16_t>((p[0] << 8) | p[1]); }
void put_i16(uint8_t* p, int16_t v) { put_u16(p, static_cast<uint16_t>(v)); }
int16_t get_i16(const uint8_t* p) { return static_cast<int16_t>(get_u16(p)); }

Frame make_frame(uint8_t type, uint8_t id, uint8_t count) {
  Frame f;
  f.type = type;
  f.id = id;
  f.count = count;
  return f;
}

bool is(const Frame& f, uint8_t type, uint8_t id) { return f.type == type && f.id == id; }

// Round to nearest (halves away from zero) and clamp into [lo, hi]; NaN -> 0.
long round_clamp(double x, long lo, long hi) {
  if (std::isnan(x)) return 0;
  if (x <= static_cast<double>(lo)) return lo;
  if (x >= static_cast<double>(hi)) return hi;
  return std::clamp(std::lround(x), lo, hi);
}

LightState light_from_payload(const Frame& f) {
  LightState s;
  s.control_enabled = f.payload[0] != 0;
  s.front_mode = f.payload[1];
  s.front_custom_percent = f.payload[2];
  s.rear_mode = f.payload[3];
  s.rear_custom_percent = f.payload[4];
  return s;
}

Frame light_frame(const LightState& m, uint8_t type, uint8_t id, uint8_t count) {
  Frame f = make_frame(type, id, count);
  f.payload[0] = m.control_enabled ? 1 : 0;
  f.payload[1] = m.front_mode;
  f.payload[2] = m.front_custom_percent;
  f.payload[3] = m.rear_mode;
  f.payload[4] = m.rear_custom_percent;
  return f;
}

}  // namespace

// ---------------------------------------------------------------- frame ----

uint8_t checksum(const uint8_t* first12) {
  unsigned sum = 0;
  for (size_t i = 0; i < kFrameSize - 1; ++i) sum += first12[i];
  return static_cast<uint8_t>(sum & 0xFF);
}

FrameBytes serialize(const Frame& frame) {
  FrameBytes b{};
  b[0] = kSof0;
  b[1] = kSof1;
  b[2] = kFrameLength;
  b[3] = frame.type;
  b[4] = frame.id;
  std::copy(frame.payload.begin(), frame.payload.end(), b.begin() + 5);
  b[11] = frame.count;
  b[12] = checksum(b.data());
  return b;
}

bool deserialize(const uint8_t* bytes13, Frame* out) {
  if (bytes13[0] != kSof0 || bytes13[1] != kSof1 || bytes13[2] != kFrameLength) return false;
  if (checksum(bytes13) != bytes13[12]) return false;
  out->type = bytes13[3];
  out->id = bytes13[4];
  std::copy(bytes13 + 5, bytes13 + 11, out->payload.begin());
  out->count = bytes13[11];
  return true;
}

// ------------------------------------------------------------- messages ----

Frame to_frame(const MotionCommand& m, uint8_t count) {
  Frame f = make_frame(kTypeCommand, kIdMotionCommand, count);
  f.payload[0] = m.control_mode;
  f.payload[1] = m.clear_fault ? 1 : 0;
  f.payload[2] = static_cast<uint8_t>(m.linear_percent);
  f.payload[3] = static_cast<uint8_t>(m.angular_percent);
  return f;
}

bool from_frame(const Frame& f, MotionCommand* out) {
  if (!is(f, kTypeCommand, kIdMotionCommand)) return false;
  out->control_mode = f.payload[0];
  out->clear_fault = f.payload[1] != 0;
  out->linear_percent = static_cast<int8_t>(f.payload[2]);
  out->angular_percent = static_cast<int8_t>(f.payload[3]);
  return true;
}

Frame to_frame(const SystemStatus& m, uint8_t count) {
  Frame f = make_frame(kTypeStatus, kIdSystemStatus, count);
  f.payload[0] = m.base_state;
  f.payload[1] = m.control_mode;
  put_u16(&f.payload[2], m.battery_decivolts);
  put_u16(&f.payload[4], m.fault_code);
  return f;
}

bool from_frame(const Frame& f, SystemStatus* out) {
  if (!is(f, kTypeStatus, kIdSystemStatus)) return false;
  out->base_state = f.payload[0];
  out->control_mode = f.payload[1];
  out->battery_decivolts = get_u16(&f.payload[2]);
  out->fault_code = get_u16(&f.payload[4]);
  return true;
}

Frame to_frame(const MotionStatus& m, uint8_t count) {
  Frame f = make_frame(kTypeStatus, kIdMotionStatus, count);
  put_i16(&f.payload[0], m.linear_mm_s);
  put_i16(&f.payload[2], m.angular_mrad_s);
  return f;
}

bool from_frame(const Frame& f, MotionStatus* out) {
  if (!is(f, kTypeStatus, kIdMotionStatus)) return false;
  out->linear_mm_s = get_i16(&f.payload[0]);
  out->angular_mrad_s = get_i16(&f.payload[2]);
  return true;
}

Frame to_frame(const MotorStatus& m, uint8_t count) {
  int motor = std::clamp(m.motor, 1, kMotorCount);
  Frame f = make_frame(kTypeStatus, static_cast<uint8_t>(kIdMotor1Status + motor - 1), count);
  put_u16(&f.payload[0], m.current_deciamps);
  put_i16(&f.payload[2], m.rpm);
  f.payload[4] = static_cast<uint8_t>(m.temperature_c);
  return f;
}

bool from_frame(const Frame& f, MotorStatus* out) {
  if (f.type != kTypeStatus || f.id < kIdMotor1Status || f.id >= kIdMotor1Status + kMotorCount) return false;
  out->motor = f.id - kIdMotor1Status + 1;
  out->current_deciamps = get_u16(&f.payload[0]);
  out->rpm = get_i16(&f.payload[2]);
  out->temperature_c = static_cast<int8_t>(f.payload[4]);
  return true;
}

Frame light_command_frame(const LightState& m, uint8_t count) {
  return light_frame(m, kTypeCommand, kIdLightCommand, count);
}
Frame light_status_frame(const LightState& m, uint8_t count) {
  return light_frame(m, kTypeStatus, kIdLightStatus, count);
}
bool light_command_from_frame(const Frame& f, LightState* out) {
  if (!is(f, kTypeCommand, kIdLightCommand)) return false;
  *out = light_from_payload(f);
  return true;
}
bool light_status_from_frame(const Frame& f, LightState* out) {
  if (!is(f, kTypeStatus, kIdLightStatus)) return false;
  *out = light_from_payload(f);
  return true;
}

// ------------------------------------------------------ unit conversions ----

int8_t linear_percent(double v_mps) {
  return static_cast<int8_t>(round_clamp(100.0 * v_mps / kMaxLinearMps, -100, 100));
}
int8_t angular_percent(double omega_radps) {
  return static_cast<int8_t>(round_clamp(100.0 * omega_radps / kMaxAngularRadps, -100, 100));
}
double linear_from_percent(int8_t percent) { return percent / 100.0 * kMaxLinearMps; }
double angular_from_percent(int8_t percent) { return percent / 100.0 * kMaxAngularRadps; }

int16_t linear_mm_s(double v_mps) {
  return static_cast<int16_t>(
      round_clamp(v_mps * 1e3, std::numeric_limits<int16_t>::min(), std::numeric_limits<int16_t>::max()));
}
int16_t angular_mrad_s(double omega_radps) {
  return static_cast<int16_t>(
      round_clamp(omega_radps * 1e3, std::numeric_limits<int16_t>::min(), std::numeric_limits<int16_t>::max()));
}
uint16_t battery_decivolts(double volts) {
  return static_cast<uint16_t>(round_clamp(volts * 10.0, 0, std::numeric_limits<uint16_t>::max()));
}

// ---------------------------------------------------------------- parser ----

void StreamParser::feed(const uint8_t* data, size_t size, const Handler& on_frame) {
  for (size_t i = 0; i < size; ++i) {
    buf_[buffered_++] = data[i];
    scan(on_frame);
  }
}

void StreamParser::scan(const Handler& on_frame) {
  // Re-checks the buffered prefix after every rejection, which drops one
  // byte: at most kFrameSize passes of at most kFrameSize bytes each.
  while (buffered_ > 0) {
    bool reject = false;
    if (buf_[0] != kSof0) {
      ++stats_.noise_bytes;
      reject = true;
    } else if (buffered_ >= 2 && buf_[1] != kSof1) {
      ++stats_.noise_bytes;  // a lone 5A
      reject = true;
    } else if (buffered_ >= 3 && buf_[2] != kFrameLength) {
      ++stats_.bad_length;
      reject = true;
    } else if (buffered_ == kFrameSize) {
      Frame frame;
      if (!deserialize(buf_.data(), &frame)) {
        ++stats_.bad_checksum;  // header and length were checked above
        reject = true;
      } else if (frame.type != kTypeCommand && frame.type != kTypeStatus) {
        ++stats_.bad_type;
        reject = true;
      } else {
        buffered_ = 0;
        ++stats_.frames;
        on_frame(frame);
        return;
      }
    }
    if (!reject) return;  // a valid prefix: wait for more bytes
    std::memmove(buf_.data(), buf_.data() + 1, buffered_ - 1);
    --buffered_;
  }
}

std::string to_hex(const uint8_t* data, size_t size) {
  std::string s;
  char tmp[4];
  for (size_t i = 0; i < size; ++i) {
    std::snprintf(tmp, sizeof tmp, i ? " %02X" : "%02X", data[i]);
    s += tmp;
  }
  return s;
}

}  // namespace evade::base
