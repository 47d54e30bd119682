#include "sensing/sensor_model.h"

#include <cmath>
#include <cstdio>

#include "sensing/rs_helios.h"
#include "sensing/vlp16.h"

namespace evade::sensing {

namespace {
constexpr int64_t kHourUs = vlp16::kMicrosPerHour;
// VLP-16 position packets (GPS/PPS status) are 512-byte payloads on port 8308.
constexpr size_t kVlp16PositionPacketSize = 512;

int64_t resolve_past_hour(int64_t us_past_hour, int64_t receive_utime) {
  int64_t hour_start = (receive_utime / kHourUs) * kHourUs;
  int64_t t = hour_start + (us_past_hour % kHourUs);
  if (t - receive_utime > kHourUs / 2) t -= kHourUs;
  if (receive_utime - t > kHourUs / 2) t += kHourUs;
  return t;
}

// Last firing of a packet after its first, us: a packet leaves the sensor
// after its last firing, so this is how far its receive time lags the
// first firing (network latency aside).
double vlp16_span_us(bool dual) {
  return vlp16::firing_offset_us((vlp16::kBlocksPerPacket / (dual ? 2 : 1)) - 1, 1, vlp16::kLasers - 1);
}
double rs_helios_span_us(bool dual) {
  return rs_helios::firing_offset_us((rs_helios::kBlocksPerPacket / (dual ? 2 : 1)) - 1, rs_helios::kChannels - 1);
}

class Vlp16Model : public SensorModel {
 public:
  Vlp16Model(const RangeBand& band, CountFn count) : count_(std::move(count)) {
    opt_.min_range_m = band.min_range_m;
    opt_.max_range_m = band.max_range_m;
    opt_.vertical_offset_correction = band.vertical_offset_correction;
  }
  LidarModel model() const override { return LidarModel::kVlp16; }
  bool calibrated() const override { return true; }
  bool is_calibration(const uint8_t*, size_t) const override { return false; }
  int64_t sensor_delta_us(int64_t from, int64_t to) const override {
    int64_t d = (to - from) % kHourUs;
    if (d > kHourUs / 2) d -= kHourUs;
    if (d <= -kHourUs / 2) d += kHourUs;
    return d;
  }

  PacketUse decode(const uint8_t* data, size_t size, int64_t receive_utime, std::vector<LidarReturn>* returns,
                   PacketTimes* times) override {
    if (size == kVlp16PositionPacketSize) {
      count_("position_packets", 1);
      return PacketUse::kIgnored;
    }
    vlp16::PacketInfo info;
    vlp16::PacketStatus st = vlp16::decode_packet(data, size, opt_, returns, &info);
    if (st != vlp16::PacketStatus::kOk) {
      count_(std::string("malformed_") + vlp16::to_string(st), 1);
      return PacketUse::kIgnored;
    }
    count_("data_packets", 1);
    if (info.factory != vlp16::kFactoryVlp16) {
      // Reported, not trusted: the configured model decides the decoding.
      char name[32];
      std::snprintf(name, sizeof(name), "factory_byte_0x%02x", info.factory);
      count_(name, 1);
    }
    if (info.dual_duplicates) count_("dual_duplicates", info.dual_duplicates);
    if (info.out_of_range) count_("out_of_range", info.out_of_range);
    if (info.timestamp_us_past_hour >= vlp16::kMicrosPerHour) count_("timestamp_invalid", 1);
    times->sensor_us = info.timestamp_us_past_hour % kHourUs;
    times->receive_us = receive_utime - std::llround(vlp16_span_us(info.return_mode == vlp16::kDual));
    times->absolute_us = resolve_past_hour(times->sensor_us, receive_utime);
    return PacketUse::kPoints;
  }

 private:
  CountFn count_;
  vlp16::DecodeOptions opt_;
};

class RsHeliosModel : public SensorModel {
 public:
  RsHeliosModel(const RangeBand& band, CountFn count) : count_(std::move(count)) {
    opt_.min_range_m = band.min_range_m;
    opt_.max_range_m = band.max_range_m;
  }
  LidarModel model() const override { return LidarModel::kRsHelios; }
  bool calibrated() const override { return have_calibration_; }
  bool is_calibration(const uint8_t* data, size_t size) const override {
    return rs_helios::classify(data, size) == rs_helios::PacketKind::kDifop;
  }
  int64_t sensor_delta_us(int64_t from, int64_t to) const override { return to - from; }

  PacketUse decode(const uint8_t* data, size_t size, int64_t receive_utime, std::vector<LidarReturn>* returns,
                   PacketTimes* times) override {
    switch (rs_helios::classify(data, size)) {
      case rs_helios::PacketKind::kDifop:
        return difop(data, size);
      case rs_helios::PacketKind::kMsop:
        return msop(data, size, receive_utime, returns, times);
      case rs_helios::PacketKind::kUnknown:
        break;
    }
    count_(size != rs_helios::kPacketSize ? "malformed_wrong_size" : "malformed_bad_header", 1);
    return PacketUse::kIgnored;
  }

 private:
  PacketUse difop(const uint8_t* data, size_t size) {
    rs_helios::Calibration cal;
    rs_helios::PacketStatus st = rs_helios::parse_difop(data, size, &cal);
    if (st != rs_helios::PacketStatus::kOk) {
      count_(std::string("malformed_difop_") + rs_helios::to_string(st), 1);
      return PacketUse::kIgnored;
    }
    count_("difop_packets", 1);
    calibration_ = cal;
    have_calibration_ = true;
    return PacketUse::kCalibration;
  }

  PacketUse msop(const uint8_t* data, size_t size, int64_t receive_utime, std::vector<LidarReturn>* returns,
                 PacketTimes* times) {
    if (!have_calibration_) {
      count_("msop_before_difop", 1);
      return PacketUse::kIgnored;
    }
    rs_helios::PacketInfo info;
    rs_helios::PacketStatus st = rs_helios::decode_msop(data, size, calibration_, opt_, returns, &info);
    if (st != rs_helios::PacketStatus::kOk) {
      count_(std::string("malformed_") + rs_helios::to_string(st), 1);
      return PacketUse::kIgnored;
    }
    count_("data_packets", 1);
    if (info.dual_duplicates) count_("dual_duplicates", info.dual_duplicates);
    if (info.out_of_range) count_("out_of_range", info.out_of_range);
    times->receive_us = receive_utime - std::llround(rs_helios_span_us(calibration_.return_mode == rs_helios::kDual));
    if (info.utc_us < 0) {
      count_("timestamp_invalid", 1);  // placed by its receive time instead
      times->sensor_us = times->absolute_us = times->receive_us;
    } else {
      times->sensor_us = times->absolute_us = info.utc_us;
    }
    return PacketUse::kPoints;
  }

  CountFn count_;
  rs_helios::DecodeOptions opt_;
  bool have_calibration_ = false;
  rs_helios::Calibration calibration_;
};
}  // namespace

const char* model_name(LidarModel m) { return m == LidarModel::kVlp16 ? "vlp16" : "rs_helios"; }

std::unique_ptr<SensorModel> make_sensor_model(LidarModel model, const RangeBand& band, CountFn count) {
  if (model == LidarModel::kVlp16) return std::make_unique<Vlp16Model>(band, std::move(count));
  return std::make_unique<RsHeliosModel>(band, std::move(count));
}

}  // namespace evade::sensing
