// The lidar_driver process core: raw LiDAR packets in (live UDP or a pcap
// file, fed by the process main through Core::input), or recorded
// LIDAR_SCAN messages in (log replay); LIDAR_POINTS (one per revolution),
// LIDAR_SCAN (its raw packets) and HEALTH out. Packets and scans go through
// the same LidarDecoder, so both paths give identical LIDAR_POINTS.
//
// Every output is stamped with the revolution's utime (see
// lidar_decoder.h), derived from the packets and their receive times only.
#pragma once

#include <memory>
#include <string>

#include "bus/core.h"
#include "config/config.h"
#include "config/fields.h"
#include "sensing/lidar_decoder.h"

namespace evade::sensing {

inline constexpr const char* kLidarPointsChannel = "LIDAR_POINTS";
inline constexpr const char* kLidarScanChannel = "LIDAR_SCAN";

// The `lidar_driver:` section: the socket's keys and the decoder's, all
// members under their YAML names (the decoder's inherited from
// LidarDecoderParams, which the decoder takes; its defaults are robot.yaml's).
struct LidarDriverParams : LidarDecoderParams {
  std::string bind_address = "0.0.0.0";
  int vlp16_data_port = 2368;
  int rs_helios_msop_port = 6699;
  int rs_helios_difop_port = 7788;
  int socket_receive_buffer_bytes = 4 << 20;
  bool publish_scan = true;

  template <class V>
  void fields(V& v) {
    v.field("bind_address", bind_address);
    v.rule(is_ipv4(bind_address), "bind_address", "not an IPv4 address");
    v.field("vlp16_data_port", vlp16_data_port, config::between(1, 65535));
    v.field("rs_helios_msop_port", rs_helios_msop_port, config::between(1, 65535));
    v.field("rs_helios_difop_port", rs_helios_difop_port, config::between(1, 65535));
    v.rule(rs_helios_msop_port != rs_helios_difop_port, "rs_helios_difop_port", "must differ from rs_helios_msop_port");
    v.field("socket_receive_buffer_bytes", socket_receive_buffer_bytes, config::between(65536, 1 << 30));
    v.field("cut_azimuth_deg", cut_azimuth_deg, config::between(0.0, 360.0));
    v.field("min_range_m", min_range_m, config::between(0.0, 10.0));
    v.field("max_range_m", max_range_m, config::between(0.0, max_encodable_range_m(model)));
    v.rule(max_range_m > min_range_m, "max_range_m", "must exceed min_range_m");
    v.field("vertical_offset_correction", vertical_offset_correction);
    v.choice("time_source", time_source,
             config::Choices<TimeSource>{{"receive", TimeSource::kReceive}, {"sensor", TimeSource::kSensor}});
    v.field("max_packets_per_revolution", max_packets_per_revolution, config::between(1, 100000));
    v.field("publish_scan", publish_scan);
    v.field("self_filter", self_filter);
    v.field("self_filter_margin_m", self_filter_margin_m, config::between(0.0, 1.0));
  }
  static bool is_ipv4(const std::string& address);
  static double max_encodable_range_m(LidarModel model);

  // Reads the shared `lidar:` and `robot:` sections (model, mount,
  // footprint) and the `lidar_driver:` section.
  static LidarDriverParams from_config(const config::Node& root);
  // UDP ports this model listens on.
  std::vector<int> ports() const;
};

class LidarDriverCore : public bus::Core {
 public:
  enum class Source {
    kPackets,  // live socket or pcap: call on_packet() inside Core::input()
    kScans,    // LIDAR_SCAN messages (log replay, or a log played back on the bus: --from-scan)
               // are decoded again (and not re-published)
  };
  // Scans come from a log that may be played back with jumps (lcm-logplayer-gui
  // seeks or loops): a scan whose first packet is older than the last packet
  // fed, or newer by more than this, is a discontinuity. The revolution being
  // assembled is dropped (counted as `scan_discontinuities`), so no cloud mixes
  // packets from two places in the log. A continuous stream never triggers it:
  // receive times only grow, and a spinning sensor sends packets ms apart.
  static constexpr int64_t kMaxScanGapUs = 1'000'000;
  LidarDriverCore(const LidarDriverParams& params, Source source);
  // The core of the whole configuration (LidarDriverParams::from_config);
  // throws ConfigError (file:line: key).
  static std::unique_ptr<LidarDriverCore> from_config(const config::Node& root, Source source);

  // One UDP payload at the current bus time now() (call inside input()).
  void on_packet(const uint8_t* data, size_t size);
  // Publishes the revolution being assembled (end of a capture).
  void flush();
  // Counts an input problem found before decoding (pcap: datagram on
  // another port, truncated capture) in HEALTH.
  void count_external(const std::string& counter) { count(counter); }

  const LidarDriverParams& params() const { return params_; }

 private:
  void publish_revolutions();

  LidarDriverParams params_;
  Source source_;
  LidarDecoder decoder_;
  std::vector<Revolution> done_;
  int64_t last_scan_packet_utime_ = -1;  // receive time of the last packet of the last scan fed
};

}  // namespace evade::sensing
