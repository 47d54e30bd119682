#include "sensing/lidar_driver_core.h"

#include <arpa/inet.h>

#include "sensing/rs_helios.h"
#include "sensing/vlp16.h"

namespace evade::sensing {

LidarDriverParams LidarDriverParams::from_config(const config::Node& root) {
  LidarDriverParams p;
  const config::Node lidar = root.section("lidar");
  const std::string model = lidar.get_choice("model", {"vlp16", "rs_helios"});
  p.decoder.model = model == "vlp16" ? LidarModel::kVlp16 : LidarModel::kRsHelios;
  const config::Node mount = lidar.section("mount");
  p.decoder.mount.x = mount.get<double>("x_m");
  p.decoder.mount.y = mount.get<double>("y_m");
  p.decoder.mount.z = mount.get<double>("z_m");
  p.decoder.mount.roll = mount.get_double("roll_rad", -M_PI, M_PI);
  p.decoder.mount.pitch = mount.get_double("pitch_rad", -M_PI, M_PI);
  p.decoder.mount.yaw = mount.get_double("yaw_rad", -M_PI, M_PI);

  const config::Node s = root.section("lidar_driver");
  p.bind_address = s.get<std::string>("bind_address");
  in_addr addr{};
  if (inet_pton(AF_INET, p.bind_address.c_str(), &addr) != 1) s.fail("bind_address", "not an IPv4 address");
  p.vlp16_data_port = s.get_int("vlp16_data_port", 1, 65535);
  p.rs_helios_msop_port = s.get_int("rs_helios_msop_port", 1, 65535);
  p.rs_helios_difop_port = s.get_int("rs_helios_difop_port", 1, 65535);
  if (p.rs_helios_msop_port == p.rs_helios_difop_port)
    s.fail("rs_helios_difop_port", "must differ from rs_helios_msop_port");
  p.socket_receive_buffer_bytes = s.get_int("socket_receive_buffer_bytes", 65536, 1 << 30);
  p.decoder.cut_azimuth_deg = s.get_double("cut_azimuth_deg", 0.0, 360.0);
  p.decoder.min_range_m = s.get_double("min_range_m", 0.0, 10.0);
  const double sensor_max =
      p.decoder.model == LidarModel::kVlp16 ? vlp16::kMaxEncodableRangeM : rs_helios::kMaxEncodableRangeM;
  p.decoder.max_range_m = s.get_double("max_range_m", 0.0, sensor_max);
  if (p.decoder.max_range_m <= p.decoder.min_range_m) s.fail("max_range_m", "must exceed min_range_m");
  p.decoder.vertical_offset_correction = s.get<bool>("vertical_offset_correction");
  p.decoder.time_source =
      s.get_choice("time_source", {"receive", "sensor"}) == "receive" ? TimeSource::kReceive : TimeSource::kSensor;
  p.decoder.max_packets_per_revolution = s.get_int("max_packets_per_revolution", 1, 100000);
  p.publish_scan = s.get<bool>("publish_scan");
  p.decoder.self_filter.enabled = s.get<bool>("self_filter");
  p.decoder.self_filter.margin_m = s.get_double("self_filter_margin_m", 0.0, 1.0);
  s.close();
  const config::Node robot = root.section("robot");
  p.decoder.self_filter.footprint_length_m = robot.get_positive("footprint_length_m");
  p.decoder.self_filter.footprint_width_m = robot.get_positive("footprint_width_m");
  return p;
}

std::vector<int> LidarDriverParams::ports() const {
  if (decoder.model == LidarModel::kVlp16) return {vlp16_data_port};
  return {rs_helios_msop_port, rs_helios_difop_port};
}

std::unique_ptr<LidarDriverCore> LidarDriverCore::from_config(const config::Node& root, Source source) {
  return std::make_unique<LidarDriverCore>(LidarDriverParams::from_config(root), source);
}

LidarDriverCore::LidarDriverCore(const LidarDriverParams& params, Source source)
    : bus::Core("lidar_driver"),
      params_(params),
      source_(source),
      decoder_(params.decoder, [this](const std::string& name, int64_t n) { count(name, n); }) {
  if (source == Source::kScans) {
    subscribe<evade::lidar_scan_t>(kLidarScanChannel, [this](const evade::lidar_scan_t& scan) {
      if (scan.sensor_model != model_name(params_.decoder.model)) {
        count("scan_model_mismatch");
        return;
      }
      if (!scan.packets.empty()) {
        const int64_t first = scan.packets.front().utime;
        if (last_scan_packet_utime_ >= 0 &&
            (first < last_scan_packet_utime_ || first > last_scan_packet_utime_ + kMaxScanGapUs)) {
          decoder_.discard_revolution();
          count("scan_discontinuities");
        }
        last_scan_packet_utime_ = scan.packets.back().utime;
      }
      decoder_.feed_scan(scan, &done_);
      publish_revolutions();
    });
  }
}

void LidarDriverCore::on_packet(const uint8_t* data, size_t size) {
  decoder_.feed(data, size, now(), &done_);
  publish_revolutions();
}

void LidarDriverCore::flush() {
  decoder_.flush(&done_);
  publish_revolutions();
}

void LidarDriverCore::publish_revolutions() {
  for (const Revolution& r : done_) {
    publish(kLidarPointsChannel, r.cloud);
    // A replaying core reads LIDAR_SCAN: it must not hear its own.
    if (params_.publish_scan && source_ == Source::kPackets) publish(kLidarScanChannel, r.scan);
  }
  done_.clear();
}

}  // namespace evade::sensing
