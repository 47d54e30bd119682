#include "sim/rs_helios_sim.h"

#include <cmath>
#include <stdexcept>

#include "sensing/packet_returns.h"

namespace evade::sim {
namespace h = sensing::rs_helios;
namespace {
constexpr double kDegToRad = M_PI / 180.0;
constexpr int kAzimuthCount = 36000;

int azimuth_count(double deg) {
  long c = std::lround(deg / h::kAzimuthUnitDeg) % kAzimuthCount;
  return static_cast<int>(c < 0 ? c + kAzimuthCount : c);
}
}  // namespace

const std::array<double, RsHeliosSimulator::kChannels> RsHeliosSimulator::kElevationDeg = {
    15.0,  13.0,  11.0,  9.0,   7.0,   5.5,   4.0,   2.67,  1.33,  0.0,   -1.33, -2.67, -4.0,  -5.33, -6.67, -8.0,
    -10.0, -16.0, -13.0, -19.0, -22.0, -28.0, -25.0, -31.0, -34.0, -37.0, -40.0, -43.0, -46.0, -49.0, -52.0, -55.0};

const std::array<double, RsHeliosSimulator::kChannels> RsHeliosSimulator::kHorizontalDeg = [] {
  std::array<double, kChannels> a{};
  for (int c = 0; c < kChannels; ++c) a[static_cast<size_t>(c)] = (c % 2 == 0) ? -4.0 : 4.0;
  return a;
}();

RsHeliosSimulator::RsHeliosSimulator(const LidarSimParams& params, int64_t start_us)
    : p_(params), start_us_(start_us), rng_(params.noise_seed) {
  if (p_.rate_hz != 10.0 && p_.rate_hz != 20.0)
    throw std::invalid_argument("RS-Helios rotation rate must be 10 or 20 Hz (600 or 1200 rpm)");
  mount_rotation(p_, mount_rot_);
  for (size_t c = 0; c < kChannels; ++c) {
    cos_el_[c] = std::cos(kElevationDeg[c] * kDegToRad);
    sin_el_[c] = std::sin(kElevationDeg[c] * kDegToRad);
  }
}

double RsHeliosSimulator::azimuth_at_offset(double offset_us) const {
  double turns = p_.rate_hz * offset_us * 1e-6;
  double az = 360.0 * (turns - std::floor(turns));
  return az >= 360.0 ? 0.0 : az;
}

int64_t RsHeliosSimulator::msop_ready_us() const {
  return start_us_ + static_cast<int64_t>(std::ceil(msop_offset_us(msop_made_ + 1)));
}

bool RsHeliosSimulator::difop_next() const { return difop_due_us() <= msop_ready_us(); }

int64_t RsHeliosSimulator::next_packet_ready_us() const { return difop_next() ? difop_due_us() : msop_ready_us(); }

void RsHeliosSimulator::skip_packet() {
  if (difop_next()) {
    ++difop_made_;
  } else {
    returns_.reach(revolution_at(msop_offset_us(msop_made_)));
    ++msop_made_;
  }
}

Packet RsHeliosSimulator::make_packet(const WorldAt& world) {
  if (difop_next()) {
    ++difop_made_;
    return make_difop();
  }
  return make_msop(world);
}

Packet RsHeliosSimulator::make_difop() const {
  h::DifopEncoder d;
  d.vertical_deg = kElevationDeg;
  d.horizontal_deg = kHorizontalDeg;
  d.return_mode = h::kStrongest;
  d.rpm = static_cast<uint16_t>(std::lround(p_.rate_hz * 60.0));
  return Packet::of(d.encode(), LidarPort::kDifop);
}

Ray RsHeliosSimulator::channel_ray(const Pose2& robot, double c, double s, int channel, double az0_deg) const {
  const auto ci = static_cast<size_t>(channel);
  const double az0 = az0_deg * kDegToRad;
  const double az = (az0_deg + kHorizontalDeg[ci]) * kDegToRad;
  // Sensor frame (x forward, y left, z up; azimuth clockwise): the decoder's geometry.
  double ds[3] = {cos_el_[ci] * std::cos(az), -cos_el_[ci] * std::sin(az), sin_el_[ci]};
  double os[3] = {h::kOpticalCentreOffsetM * std::cos(az0), -h::kOpticalCentreOffsetM * std::sin(az0), 0.0};
  double db[3], ob[3];  // in the base frame
  for (int i = 0; i < 3; ++i) {
    db[i] = mount_rot_[i][0] * ds[0] + mount_rot_[i][1] * ds[1] + mount_rot_[i][2] * ds[2];
    ob[i] = mount_rot_[i][0] * os[0] + mount_rot_[i][1] * os[1] + mount_rot_[i][2] * os[2];
  }
  ob[0] += p_.mount_x_m;
  ob[1] += p_.mount_y_m;
  ob[2] += p_.mount_height_m;
  Ray r;
  r.origin = Vec3{robot.x + c * ob[0] - s * ob[1], robot.y + s * ob[0] + c * ob[1], ob[2]};
  r.dir = Vec3{c * db[0] - s * db[1], s * db[0] + c * db[1], db[2]};
  return r;
}

double RsHeliosSimulator::cast_distance(const Ray& ray, const WorldSnapshot& snap, int* hit) {
  double range = hit_ground(ray);
  *hit = -1;
  for (size_t i = 0; i < snap.solids.size(); ++i) {
    double t = hit_solid(ray, snap.solids[i]);
    if (t < range) {
      range = t;
      *hit = static_cast<int>(i);
    }
  }
  if (!(range <= p_.max_range_m)) return 0.0;  // no return
  double d = range + (p_.range_noise_std_m > 0.0 ? p_.range_noise_std_m * noise_(rng_) : 0.0);
  return d < h::kDistanceUnitM ? 0.0 : d;  // noise cannot make a negative range
}

Packet RsHeliosSimulator::make_msop(const WorldAt& world) {
  const double t0 = msop_offset_us(msop_made_);
  h::MsopEncoder enc;
  enc.utc_us = start_us_ + std::llround(t0);
  enc.index = static_cast<uint32_t>(msop_made_);
  int count[h::kBlocksPerPacket];
  for (int b = 0; b < h::kBlocksPerPacket; ++b) count[b] = azimuth_count(azimuth_at_offset(t0 + b * h::kBlockPeriodUs));
  double gap_deg[h::kBlocksPerPacket];
  sensing::column_gaps(count, h::kBlocksPerPacket, 1, gap_deg);

  WorldSnapshot snap;
  for (int b = 0; b < h::kBlocksPerPacket; ++b) {
    auto& block = enc.blocks[static_cast<size_t>(b)];
    block.azimuth_deg = count[b] * h::kAzimuthUnitDeg;
    // One snapshot per block (55.56 us): the robot moves a few hundredths of a millimetre in it.
    const double block_us = t0 + h::firing_offset_us(b, 0);
    world(start_us_ + std::llround(block_us), &snap);
    const int64_t revolution = revolution_at(block_us);
    returns_.reach(revolution);
    const double cos_yaw = std::cos(snap.robot.yaw), sin_yaw = std::sin(snap.robot.yaw);
    for (int c = 0; c < kChannels; ++c) {
      const double az0 = block.azimuth_deg + gap_deg[b] * (c * h::kChannelIntervalUs) / h::kBlockPeriodUs;
      int hit = -1;
      block.distance_m[c] = cast_distance(channel_ray(snap.robot, cos_yaw, sin_yaw, c, az0), snap, &hit);
      block.intensity[c] = hit < 0 ? p_.ground_reflectivity : p_.obstacle_reflectivity;
      if (hit >= 0 && block.distance_m[c] > 0.0) returns_.add(revolution, static_cast<size_t>(hit));
    }
  }
  ++msop_made_;
  return Packet::of(enc.encode(), LidarPort::kData);
}

}  // namespace evade::sim
