// From raw UDP payloads to one point cloud per revolution, for either
// sensor model (sensor_model.h decodes the packets; this file assembles
// them). Stateful (calibration, the revolution being assembled) but
// clock-free: every time comes from the packets and their receive times,
// so feeding the same packets with the same receive times gives the same
// clouds, live or in a log replay.
//
// Revolutions are cut between firings, where the firing azimuth passes
// `cut_azimuth_deg` (at most one cut per packet; a revolution is also cut
// when it holds `max_packets_per_revolution` packets, e.g. a stopped motor;
// packets that yield no point at all are not kept beyond that either).
//
// Time. Each packet carries the sensor's time of its first firing (VLP-16:
// microseconds past the hour; RS-Helios: UTC). A revolution is anchored at
// its first packet: anchor time = that packet's receive time minus the
// packet's span (it is sent after its last firing), or, with
// time_source = sensor, the sensor time (a VLP-16's us-past-hour resolved
// to the hour nearest the receive time). Points are then placed with the
// sensor clock relative to the anchor plus the firing timing, so the
// offsets within a revolution are exact whatever the network jitter. The
// cloud's utime is the time of its first point; time_offset[i] is relative
// to it.
//
// Returns over the robot's own footprint (self_filter.h) are dropped after
// the cut and time logic, so they change nothing but the points.
//
// The raw packets that made a revolution (every accepted packet, including
// RS-Helios DIFOPs; the packet in which the cut falls belongs to the
// revolution it completes) come back with it as a lidar_scan_t, and
// feed_scan() re-runs them: replaying a LIDAR_SCAN stream reproduces the
// LIDAR_POINTS stream exactly (a scan whose packets complete no
// revolution is the flushed last one, and is flushed again).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "evade/lidar_scan_t.hpp"
#include "evade/pointcloud_t.hpp"
#include "sensing/lidar_return.h"
#include "sensing/self_filter.h"
#include "sensing/sensor_model.h"

namespace evade::sensing {

enum class TimeSource { kReceive, kSensor };

// What decoding takes. The first members are the `lidar_driver:` keys of
// config/robot.yaml under their names, with the file's values as defaults
// (listed, with their ranges, by LidarDriverParams::fields); the model,
// mount and footprint come from the shared `lidar:` and `robot:` sections
// (LidarDriverParams::from_config).
struct LidarDecoderParams {
  double cut_azimuth_deg = 0.0;  // revolutions start when the firing azimuth passes this
  double min_range_m = 0.4;      // returns outside [min, max] are dropped (counted)
  double max_range_m = 100.0;
  bool vertical_offset_correction = true;  // VLP-16 per-laser beam origin height (vlp16.h)
  TimeSource time_source = TimeSource::kReceive;
  int max_packets_per_revolution = 1000;  // raw packets held for one revolution / LIDAR_SCAN
  bool self_filter = true;                // returns over the robot's footprint are dropped (counted)
  double self_filter_margin_m = 0.05;     // the footprint grown by this on every side (self_filter.h)

  LidarModel model = LidarModel::kVlp16;  // lidar.model
  evade::pose3d_t mount{};                // lidar.mount
  double footprint_length_m = 0.42;       // robot.footprint_length_m
  double footprint_width_m = 0.31;        // robot.footprint_width_m
};

struct Revolution {
  evade::pointcloud_t cloud;
  evade::lidar_scan_t scan;
};

class LidarDecoder {
 public:
  // count(name, n): every packet and problem is counted by name
  // ("data_packets", "malformed_wrong_size", ...) for HEALTH.
  using CountFn = sensing::CountFn;

  LidarDecoder(const LidarDecoderParams& params, CountFn count);

  // One UDP payload as received, at host time `receive_utime` (us).
  // Completed revolutions are appended to `out`.
  void feed(const uint8_t* data, size_t size, int64_t receive_utime, std::vector<Revolution>* out);
  // Emits the revolution being assembled, if it holds any point.
  void flush(std::vector<Revolution>* out);
  // Replays a recorded LIDAR_SCAN (see above).
  void feed_scan(const evade::lidar_scan_t& scan, std::vector<Revolution>* out);
  // Drops the revolution being assembled and the azimuth it reached (the
  // packet stream was interrupted: the next packet starts afresh).
  void discard_revolution();

  const LidarDecoderParams& params() const { return params_; }
  bool calibrated() const { return sensor_->calibrated(); }

 private:
  void add_packet_returns(const PacketTimes& times, const uint8_t* data, size_t size, int64_t receive_utime,
                          std::vector<Revolution>* out);
  void emit(std::vector<Revolution>* out);
  // Keeps the raw packets held for the next LIDAR_SCAN under
  // max_packets_per_revolution (forced cut, or dropping point-less packets).
  void bound_pending(std::vector<Revolution>* out);
  void start_revolution();
  void record_packet(const uint8_t* data, size_t size, int64_t receive_utime);

  LidarDecoderParams params_;
  CountFn count_;
  std::unique_ptr<SensorModel> sensor_;  // the model's packet decoding (sensor_model.h)
  SelfFilter self_filter_;
  std::vector<LidarReturn> returns_;  // scratch, one packet

  // the revolution being assembled
  Revolution rev_;
  std::vector<double> rel_us_;  // point times relative to the anchor
  bool anchored_ = false;
  PacketTimes anchor_{};
  int64_t anchor_time_us_ = 0;
  bool have_prev_azimuth_ = false;
  double prev_rel_azimuth_ = 0.0;
};

}  // namespace evade::sensing
