// The simulated RoboSense RS-Helios-5515 (32 channels, +15 to -55 deg):
// MSOP point packets at the sensor's rate (12 blocks of 55.56 us, so one
// packet every 666.72 us, 1499.9 packets/s at any rotation rate) and a
// DIFOP every second, the first at the start (the driver decodes nothing
// before it). Packets are lib/sensing's encoders' bytes, single return
// (strongest).
//
// What the DIFOP carries, and the sim casts with: kElevationDeg, the
// RS-Helios-5515's nominal channel elevations (channel 1 = +15 deg ...
// channel 32 = -55 deg, as RoboSense's manual lists them and as published
// calibration files carry them, e.g. tier4/nebula Helios5515.csv), and
// kHorizontalDeg, a per-channel azimuth correction of -4 / +4 deg on
// alternate channels, the size a real unit's two laser boards show, so that
// the decoder's correction is exercised.
//
// Exact agreement with the decoder (lib/sensing/rs_helios.h): block
// azimuths are quantised to 0.01 deg before casting; channel c is cast at
// the azimuth the decoder will give it (block azimuth + gap to the next
// block x c * 1.73 / 55.56, then + its horizontal correction) from the
// optical centre the decoder assumes (34.98 mm off the rotation axis along
// the uncorrected azimuth). The decoded point is then on the true surface
// up to the 2.5 mm distance unit and the configured range noise.
#pragma once

#include <array>
#include <cstdint>
#include <random>

#include "sensing/rs_helios.h"
#include "sim/lidar_sim.h"

namespace evade::sim {

class RsHeliosSimulator : public LidarSimulator {
 public:
  static constexpr int kChannels = sensing::rs_helios::kChannels;
  static constexpr double kPacketPeriodUs =
      sensing::rs_helios::kBlocksPerPacket * sensing::rs_helios::kBlockPeriodUs;  // 666.72 us
  static constexpr int64_t kDifopPeriodUs = 1'000'000;
  static const std::array<double, kChannels> kElevationDeg;
  static const std::array<double, kChannels> kHorizontalDeg;

  // The sweep starts at azimuth 0 at `start_us`. rate_hz: 10 or 20 (600 or
  // 1200 rpm, reported in the DIFOP).
  RsHeliosSimulator(const LidarSimParams& params, int64_t start_us);

  int64_t next_packet_ready_us() const override;
  Packet make_packet(const WorldAt& world) override;
  void skip_packet() override;
  int64_t packets_made() const override { return msop_made_ + difop_made_; }

  int64_t msop_made() const { return msop_made_; }
  int64_t difop_made() const { return difop_made_; }
  // First firing of MSOP packet k, us after the start.
  static double msop_offset_us(int64_t k) { return k * kPacketPeriodUs; }
  double azimuth_at_offset(double offset_us) const;
  // The ray of `channel` at uncorrected azimuth `az0_deg` from pose `robot`.
  Ray channel_ray(const Pose2& robot, double cos_yaw, double sin_yaw, int channel, double az0_deg) const;

 private:
  bool difop_next() const;
  int64_t msop_ready_us() const;
  int64_t difop_due_us() const { return start_us_ + difop_made_ * kDifopPeriodUs; }
  Packet make_msop(const WorldAt& world);
  Packet make_difop() const;
  double cast_distance(const Ray& ray, const WorldSnapshot& snap, bool* ground);

  LidarSimParams p_;
  int64_t start_us_;
  int64_t msop_made_ = 0, difop_made_ = 0;
  std::mt19937_64 rng_;
  std::normal_distribution<double> noise_{0.0, 1.0};
  double mount_rot_[3][3];
  std::array<double, kChannels> cos_el_{}, sin_el_{};
};

}  // namespace evade::sim
