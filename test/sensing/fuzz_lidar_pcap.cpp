// libFuzzer target: capture files. The input is a pcap file in memory; every
// UDP datagram the reader finds goes through a VLP-16 and an RS-Helios
// decoder (with the footprint self-filter), as in `lidar_driver --pcap`. Malformed headers, link types, IP/UDP lengths
// and truncated records must be skipped, never crash.
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "sensing/lidar_decoder.h"
#include "sensing/packet_sources.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  std::vector<uint8_t> copy(data, data + size);  // fmemopen wants a mutable buffer
  FILE* f = fmemopen(copy.data(), copy.size(), "rb");
  if (!f) return 0;
  try {
    evade::sensing::PcapUdpReader reader(f, "fuzz input");
    evade::sensing::LidarDecoderParams vlp16_params;
    vlp16_params.min_range_m = 0.0;
    vlp16_params.max_range_m = 200.0;
    vlp16_params.self_filter = false;
    evade::sensing::LidarDecoder dec(vlp16_params, nullptr);
    evade::sensing::LidarDecoderParams helios_params;
    helios_params.model = evade::sensing::LidarModel::kRsHelios;
    helios_params.min_range_m = 0.0;
    helios_params.max_range_m = 200.0;
    helios_params.footprint_length_m = 0.93;
    helios_params.footprint_width_m = 0.70;
    evade::sensing::LidarDecoder helios(helios_params, nullptr);
    std::vector<evade::sensing::Revolution> out;
    evade::sensing::UdpDatagram d;
    for (int i = 0; i < 10000 && reader.next(&d); ++i) {
      if (d.truncated) continue;
      dec.feed(d.payload.data(), d.payload.size(), d.utime, &out);
      helios.feed(d.payload.data(), d.payload.size(), d.utime, &out);
      out.clear();
    }
    dec.flush(&out);
    helios.flush(&out);
  } catch (const std::runtime_error&) {
    // not a capture we can read: rejected with a reason, as intended
  }
  return 0;
}
