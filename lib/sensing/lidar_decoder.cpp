#include "sensing/lidar_decoder.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "sensing/vlp16.h"

namespace evade::sensing {

namespace {
// A sensor clock step larger than this between two packets of one
// revolution is a clock jump (sync, reset), not rotation: the receive
// times place that packet instead.
constexpr int64_t kMaxSensorStepUs = 1'000'000;
// Receive times (us since the epoch) beyond year 2286 come from a corrupt
// LIDAR_SCAN, not a clock: refused, so time arithmetic cannot overflow.
constexpr int64_t kMaxReceiveUtime = 9'999'999'999'000'000LL;

int32_t clamp_int32(double v) {
  if (!(v > std::numeric_limits<int32_t>::min())) return std::numeric_limits<int32_t>::min();
  if (!(v < std::numeric_limits<int32_t>::max())) return std::numeric_limits<int32_t>::max();
  return static_cast<int32_t>(std::llround(v));
}
}  // namespace

LidarDecoder::LidarDecoder(const LidarDecoderParams& params, CountFn count)
    : params_(params), count_(std::move(count)), self_filter_(params) {
  if (!count_) count_ = [](const std::string&, int64_t) {};
  sensor_ = make_sensor_model(
      params.model, RangeBand{params.min_range_m, params.max_range_m, params.vertical_offset_correction}, count_);
  returns_.reserve(static_cast<size_t>(vlp16::kBlocksPerPacket * vlp16::kReturnsPerBlock));
  start_revolution();
}

void LidarDecoder::start_revolution() {
  // Room for as many points as the last revolution had: one allocation per
  // array and revolution in steady state.
  const size_t expected = rel_us_.size() + rel_us_.size() / 8;
  rev_ = Revolution{};
  rev_.cloud.x.reserve(expected);
  rev_.cloud.y.reserve(expected);
  rev_.cloud.z.reserve(expected);
  rev_.cloud.intensity.reserve(expected);
  rev_.cloud.ring.reserve(expected);
  rel_us_.clear();
  rel_us_.reserve(expected);
  anchored_ = false;
}

void LidarDecoder::record_packet(const uint8_t* data, size_t size, int64_t receive_utime) {
  evade::lidar_packet_t p;
  p.utime = receive_utime;
  p.size = static_cast<int32_t>(size);
  p.data.assign(data, data + size);
  rev_.scan.packets.push_back(std::move(p));
}

void LidarDecoder::bound_pending(std::vector<Revolution>* out) {
  auto& pending = rev_.scan.packets;
  if (static_cast<int>(pending.size()) < params_.max_packets_per_revolution) return;
  if (!rel_us_.empty()) {
    count_("forced_cuts", 1);  // the azimuth never wrapped: a stopped motor, a bad cut angle
    emit(out);
    return;
  }
  // Packets without a single point (a covered sensor, everything out of
  // range) would pile up forever. They changed nothing a replay needs but
  // the calibration, so only the last DIFOP is kept.
  evade::lidar_packet_t last_difop;
  bool have_difop = false;
  for (auto& p : pending)
    if (sensor_->is_calibration(p.data.data(), p.data.size())) {
      last_difop = std::move(p);
      have_difop = true;
    }
  count_("empty_packets_dropped", static_cast<int64_t>(pending.size()) - (have_difop ? 1 : 0));
  pending.clear();
  if (have_difop) pending.push_back(std::move(last_difop));
}

void LidarDecoder::feed(const uint8_t* data, size_t size, int64_t receive_utime, std::vector<Revolution>* out) {
  returns_.clear();
  if (receive_utime < 0 || receive_utime > kMaxReceiveUtime) {
    count_("malformed_receive_time", 1);
    return;
  }
  PacketTimes times{};
  switch (sensor_->decode(data, size, receive_utime, &returns_, &times)) {
    case PacketUse::kIgnored:
      return;
    case PacketUse::kCalibration:
      bound_pending(out);
      record_packet(data, size, receive_utime);
      return;
    case PacketUse::kPoints:
      break;
  }
  add_packet_returns(times, data, size, receive_utime, out);
}

void LidarDecoder::add_packet_returns(const PacketTimes& times, const uint8_t* data, size_t size, int64_t receive_utime,
                                      std::vector<Revolution>* out) {
  bound_pending(out);
  record_packet(data, size, receive_utime);
  bool cut_done = false;
  bool packet_counted = false;
  // The packet's time relative to the revolution's anchor, from the sensor
  // clock unless that jumped; recomputed when a cut re-anchors.
  double packet_rel_us = 0.0;
  bool rel_valid = false;
  float last_firing_az = -1.0f;
  int64_t self_filtered = 0;
  for (const LidarReturn& r : returns_) {
    if (r.firing_azimuth_deg != last_firing_az) {  // a new firing: may cut
      last_firing_az = r.firing_azimuth_deg;
      double rel_az = r.firing_azimuth_deg - params_.cut_azimuth_deg;
      if (rel_az < 0.0) rel_az += 360.0;
      // The firing azimuth passed the cut angle when it wraps from near 360 to near 0.
      if (have_prev_azimuth_ && !cut_done && rel_az + 180.0 < prev_rel_azimuth_) {
        cut_done = true;
        if (!rel_us_.empty()) {
          emit(out);  // this packet stays in the emitted revolution's scan
          packet_counted = false;
          rel_valid = false;
        }
      }
      prev_rel_azimuth_ = rel_az;
      have_prev_azimuth_ = true;
    }
    if (!anchored_) {
      anchor_ = times;
      anchor_time_us_ = params_.time_source == TimeSource::kSensor ? times.absolute_us : times.receive_us;
      anchored_ = true;
    }
    if (!packet_counted) {
      ++rev_.cloud.packets;
      packet_counted = true;
    }
    if (!rel_valid) {
      int64_t d = sensor_->sensor_delta_us(anchor_.sensor_us, times.sensor_us);
      if (d > kMaxSensorStepUs || d < -kMaxSensorStepUs) {
        count_("sensor_time_jumps", 1);
        d = params_.time_source == TimeSource::kSensor ? times.absolute_us - anchor_.absolute_us
                                                       : times.receive_us - anchor_.receive_us;
      }
      packet_rel_us = static_cast<double>(d);
      rel_valid = true;
    }
    if (self_filter_.enabled() && self_filter_.inside(r.x, r.y, r.z)) {
      ++self_filtered;
      continue;
    }
    evade::pointcloud_t& c = rev_.cloud;
    c.x.push_back(r.x);
    c.y.push_back(r.y);
    c.z.push_back(r.z);
    c.intensity.push_back(r.intensity);
    c.ring.push_back(static_cast<int8_t>(r.ring));
    rel_us_.push_back(packet_rel_us + r.time_offset_us);
  }
  if (self_filtered > 0) count_("self_filtered_points", self_filtered);
}

void LidarDecoder::emit(std::vector<Revolution>* out) {
  evade::pointcloud_t& c = rev_.cloud;
  c.n = static_cast<int32_t>(c.x.size());
  const double first = rel_us_.empty() ? 0.0 : rel_us_.front();
  c.utime = anchor_time_us_ + std::llround(first);
  c.time_offset.resize(rel_us_.size());
  for (size_t i = 0; i < rel_us_.size(); ++i) c.time_offset[i] = clamp_int32(rel_us_[i] - first);
  c.sensor_model = model_name(sensor_->model());
  c.mount = params_.mount;
  rev_.scan.utime = c.utime;
  rev_.scan.sensor_model = c.sensor_model;
  rev_.scan.num_packets = static_cast<int32_t>(rev_.scan.packets.size());
  count_("revolutions", 1);
  out->push_back(std::move(rev_));
  start_revolution();
}

void LidarDecoder::flush(std::vector<Revolution>* out) {
  if (!rel_us_.empty()) emit(out);
}

void LidarDecoder::discard_revolution() {
  start_revolution();
  have_prev_azimuth_ = false;
}

void LidarDecoder::feed_scan(const evade::lidar_scan_t& scan, std::vector<Revolution>* out) {
  const size_t before = out->size();
  for (const auto& p : scan.packets) {
    if (p.size != static_cast<int32_t>(p.data.size())) {
      count_("malformed_scan_packet", 1);
      continue;
    }
    feed(p.data.data(), p.data.size(), p.utime, out);
  }
  if (out->size() == before) flush(out);
}

}  // namespace evade::sensing
