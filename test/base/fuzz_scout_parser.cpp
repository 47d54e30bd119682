// libFuzzer entry point for the Scout UART v1 stream parser and frame
// decoders. The first input byte chooses how the rest is cut into reads
// (1..32 bytes each), so split frames are explored as well as content.
//
// Checked on every input (a violation traps, which the fuzzer reports):
// - every byte fed is accounted for exactly once: 13 per delivered frame,
//   one per rejection (noise, bad length, bad checksum, bad type), plus
//   what is still buffered (< 13);
// - every delivered frame re-serialises to a frame that deserialize()
//   accepts, and the decoder for its kind round-trips its payload.
#include <cstddef>
#include <cstdint>

#include "base/scout_protocol.h"

namespace {

void check(bool ok) {
  if (!ok) __builtin_trap();
}

void check_frame(const evade::base::Frame& f) {
  using namespace evade::base;
  FrameBytes b = serialize(f);
  Frame again;
  check(deserialize(b.data(), &again));
  check(again.type == f.type && again.id == f.id && again.payload == f.payload && again.count == f.count);
  MotionCommand mc;
  SystemStatus ss;
  MotionStatus ms;
  MotorStatus mo;
  LightState ls;
  if (from_frame(f, &mc)) {
    Frame r = to_frame(mc, f.count);
    check(r.payload[2] == f.payload[2] && r.payload[3] == f.payload[3]);
  }
  if (from_frame(f, &ss)) check(to_frame(ss, f.count).payload == f.payload);
  if (from_frame(f, &ms)) {
    Frame r = to_frame(ms, f.count);
    for (int i = 0; i < 4; ++i) check(r.payload[i] == f.payload[i]);
  }
  if (from_frame(f, &mo)) {
    Frame r = to_frame(mo, f.count);
    check(r.id == f.id);
    for (int i = 0; i < 5; ++i) check(r.payload[i] == f.payload[i]);
  }
  if (light_status_from_frame(f, &ls) || light_command_from_frame(f, &ls)) {
    check(ls.front_mode == f.payload[1] && ls.rear_custom_percent == f.payload[4]);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace evade::base;
  if (size == 0) return 0;
  const size_t chunk = 1 + data[0] % 32;
  ++data;
  --size;
  StreamParser parser;
  uint64_t delivered = 0;
  for (size_t pos = 0; pos < size; pos += chunk) {
    const size_t n = size - pos < chunk ? size - pos : chunk;
    parser.feed(data + pos, n, [&](const Frame& f) {
      ++delivered;
      check_frame(f);
    });
  }
  const ParserStats& s = parser.stats();
  check(s.frames == delivered);
  check(parser.buffered() < kFrameSize);
  check(s.frames * kFrameSize + s.noise_bytes + s.bad_length + s.bad_checksum + s.bad_type + parser.buffered() == size);
  return 0;
}
