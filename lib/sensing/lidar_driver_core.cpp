#include "sensing/lidar_driver_core.h"

#include <arpa/inet.h>

#include "config/robot_params.h"
#include "sensing/rs_helios.h"
#include "sensing/vlp16.h"

namespace evade::sensing {

bool LidarDriverParams::is_ipv4(const std::string& address) {
  in_addr addr{};
  return inet_pton(AF_INET, address.c_str(), &addr) == 1;
}

double LidarDriverParams::max_encodable_range_m(LidarModel model) {
  return model == LidarModel::kVlp16 ? vlp16::kMaxEncodableRangeM : rs_helios::kMaxEncodableRangeM;
}

LidarDriverParams LidarDriverParams::from_config(const config::Node& root) {
  const config::LidarParams lidar = config::load<config::LidarParams>(root.section("lidar"));
  LidarDriverParams p;
  p.model = lidar.model == "vlp16" ? LidarModel::kVlp16 : LidarModel::kRsHelios;
  p.mount.x = lidar.mount.x_m;
  p.mount.y = lidar.mount.y_m;
  p.mount.z = lidar.mount.z_m;
  p.mount.roll = lidar.mount.roll_rad;
  p.mount.pitch = lidar.mount.pitch_rad;
  p.mount.yaw = lidar.mount.yaw_rad;
  config::load_into(root.section("lidar_driver"), p);
  const config::RobotParams robot = config::load<config::RobotParams>(root.section("robot"));
  p.footprint_length_m = robot.footprint_length_m;
  p.footprint_width_m = robot.footprint_width_m;
  return p;
}

std::vector<int> LidarDriverParams::ports() const {
  if (model == LidarModel::kVlp16) return {vlp16_data_port};
  return {rs_helios_msop_port, rs_helios_difop_port};
}

std::unique_ptr<LidarDriverCore> LidarDriverCore::from_config(const config::Node& root, Source source) {
  return std::make_unique<LidarDriverCore>(LidarDriverParams::from_config(root), source);
}

LidarDriverCore::LidarDriverCore(const LidarDriverParams& params, Source source)
    : bus::Core("lidar_driver"),
      params_(params),
      source_(source),
      decoder_(params, [this](const std::string& name, int64_t n) { count(name, n); }) {
  if (source == Source::kScans) {
    subscribe<evade::lidar_scan_t>(kLidarScanChannel, [this](const evade::lidar_scan_t& scan) {
      if (scan.sensor_model != model_name(params_.model)) {
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
