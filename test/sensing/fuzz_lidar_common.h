// Shared body of the LiDAR fuzz targets. The input is read two ways:
//   1. as one UDP payload, straight into the stateless packet decoder(s);
//   2. as a stream of packets, each [uint16 little-endian length][bytes],
//      fed with advancing receive times through a LidarDecoder, whose
//      LIDAR_SCAN records are then replayed through a second decoder: the
//      clouds must come out byte-identical (the replay contract), else the
//      target aborts. Nothing may crash, hang or read out of bounds. Half
//      the inputs run with the footprint self-filter on.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <vector>

#include "sensing/lidar_decoder.h"
#include "sensing/rs_helios.h"
#include "sensing/vlp16.h"

namespace evade::sensing::fuzz {

template <class Msg>
std::vector<uint8_t> encoded(const Msg& m) {
  std::vector<uint8_t> b(static_cast<size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

inline int fuzz_lidar(LidarModel model, const uint8_t* data, size_t size) {
  std::vector<LidarReturn> returns;
  if (model == LidarModel::kVlp16) {
    vlp16::PacketInfo info;
    vlp16::decode_packet(data, size, {}, &returns, &info);
  } else {
    rs_helios::Calibration cal;
    rs_helios::parse_difop(data, size, &cal);
    for (int c = 0; c < rs_helios::kChannels; ++c) cal.vertical_deg[c] = -16.0 + c;
    cal.update_trig();
    cal.return_mode = (size > 0 && (data[0] & 1)) ? rs_helios::kDual : rs_helios::kStrongest;
    rs_helios::decode_msop(data, size, cal, {}, &returns, nullptr);
  }

  LidarDecoderParams p;
  p.model = model;
  p.min_range_m = 0.0;
  p.max_range_m = 200.0;
  p.self_filter = false;
  p.max_packets_per_revolution = 8;
  if (size > 0) {
    p.cut_azimuth_deg = (data[0] >> 1) * (360.0 / 128.0);
    p.time_source = (size > 1 && (data[1] & 1)) ? TimeSource::kSensor : TimeSource::kReceive;
    // The footprint self-filter on half the inputs, under a tilted mount.
    p.self_filter = size > 1 && (data[1] & 2) != 0;
    p.footprint_length_m = 0.93;
    p.footprint_width_m = 0.70;
    p.mount.z = 0.9;
    p.mount.pitch = size > 1 ? (data[1] >> 2) * 0.01 : 0.0;
  }
  LidarDecoder live(p, nullptr);
  std::vector<Revolution> revs;
  int64_t receive_us = 1'700'000'000'000'000LL;
  size_t off = 2;
  while (off + 2 <= size) {
    const size_t len = static_cast<size_t>(data[off] | (data[off + 1] << 8));
    off += 2;
    const size_t n = len < size - off ? len : size - off;
    live.feed(data + off, n, receive_us, &revs);
    receive_us += 1000 + (n > 0 ? data[off] : 0);
    off += n;
  }
  live.flush(&revs);

  LidarDecoder replay(p, nullptr);
  std::vector<Revolution> again;
  for (const auto& r : revs) replay.feed_scan(r.scan, &again);
  if (again.size() != revs.size()) std::abort();
  for (size_t i = 0; i < revs.size(); ++i) {
    if (revs[i].cloud.n != static_cast<int32_t>(revs[i].cloud.x.size())) std::abort();
    if (encoded(revs[i].cloud) != encoded(again[i].cloud)) std::abort();
  }
  return 0;
}

}  // namespace evade::sensing::fuzz
