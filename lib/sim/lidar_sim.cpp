#include "sim/lidar_sim.h"

#include <cmath>
#include <stdexcept>

#include "sensing/packet_returns.h"
#include "sim/rs_helios_sim.h"

namespace evade::sim {
namespace v = sensing::vlp16;
namespace {
constexpr double kDegToRad = M_PI / 180.0;
constexpr int64_t kMicrosPerHour = v::kMicrosPerHour;

}  // namespace

void mount_rotation(const LidarSimParams& p, double out[3][3]) {
  double cr = std::cos(p.mount_roll_rad), sr = std::sin(p.mount_roll_rad);
  double cp = std::cos(p.mount_pitch_rad), sp = std::sin(p.mount_pitch_rad);
  double cy = std::cos(p.mount_yaw_rad), sy = std::sin(p.mount_yaw_rad);
  // R = Rz(yaw) Ry(pitch) Rx(roll)
  double r[3][3] = {{cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr},
                    {sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr},
                    {-sp, cp * sr, cp * cr}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out[i][j] = r[i][j];
}

std::unique_ptr<LidarSimulator> make_lidar_simulator(const std::string& model, const LidarSimParams& params,
                                                     int64_t start_us) {
  if (model == "vlp16") return std::make_unique<Vlp16Simulator>(params, start_us);
  if (model == "rs_helios") return std::make_unique<RsHeliosSimulator>(params, start_us);
  throw std::invalid_argument("unknown LiDAR model '" + model + "' (vlp16 | rs_helios)");
}

Vlp16Simulator::Vlp16Simulator(const LidarSimParams& params, int64_t start_us)
    : p_(params), start_us_(start_us), rng_(params.noise_seed) {
  mount_rotation(p_, mount_rot_);
  for (int l = 0; l < v::kLasers; ++l) {
    const double el = v::kLaserTable[static_cast<size_t>(l)].elevation_deg * kDegToRad;
    cos_el_[static_cast<size_t>(l)] = std::cos(el);
    sin_el_[static_cast<size_t>(l)] = std::sin(el);
  }
}

void Vlp16Simulator::skip_packet() {
  returns_.reach(revolution_at(packet_offset_us(next_packet_)));
  ++next_packet_;
}

int64_t Vlp16Simulator::next_packet_ready_us() const {
  return start_us_ + static_cast<int64_t>(std::ceil(packet_offset_us(next_packet_ + 1)));
}

double Vlp16Simulator::azimuth_at_offset(double offset_us) const {
  double turns = p_.rate_hz * offset_us * 1e-6;
  double az = 360.0 * (turns - std::floor(turns));
  return az >= 360.0 ? 0.0 : az;
}

Ray Vlp16Simulator::laser_ray(const Pose2& robot, int laser, double azimuth_deg) const {
  return laser_ray(robot, std::cos(robot.yaw), std::sin(robot.yaw), laser, azimuth_deg);
}

Ray Vlp16Simulator::laser_ray(const Pose2& robot, double c, double s, int laser, double azimuth_deg) const {
  const auto li = static_cast<size_t>(laser);
  const v::Laser& l = v::kLaserTable[li];
  const double az = azimuth_deg * kDegToRad;
  // Direction and beam origin in the sensor frame (x forward, y left, z up;
  // Velodyne's azimuth turns clockwise, hence -sin): see sensing/vlp16.h.
  double ds[3] = {cos_el_[li] * std::cos(az), -cos_el_[li] * std::sin(az), sin_el_[li]};
  double os[3] = {0.0, 0.0, l.vertical_offset_m};
  double db[3], ob[3];  // in the base frame
  for (int i = 0; i < 3; ++i) {
    db[i] = mount_rot_[i][0] * ds[0] + mount_rot_[i][1] * ds[1] + mount_rot_[i][2] * ds[2];
    ob[i] = mount_rot_[i][0] * os[0] + mount_rot_[i][1] * os[1] + mount_rot_[i][2] * os[2];
  }
  ob[0] += p_.mount_x_m;
  ob[1] += p_.mount_y_m;
  ob[2] += p_.mount_height_m;  // base frame origin on the ground
  Ray r;
  r.origin = Vec3{robot.x + c * ob[0] - s * ob[1], robot.y + s * ob[0] + c * ob[1], ob[2]};
  r.dir = Vec3{c * db[0] - s * db[1], s * db[0] + c * db[1], db[2]};
  return r;
}

Packet Vlp16Simulator::make_packet(const WorldAt& world) {
  const double t0 = packet_offset_us(next_packet_);  // us after start_us_
  v::PacketEncoder enc;
  int64_t first_firing_us = start_us_ + std::llround(t0);
  enc.timestamp_us_past_hour =
      static_cast<uint32_t>(((first_firing_us % kMicrosPerHour) + kMicrosPerHour) % kMicrosPerHour);
  enc.return_mode = v::kStrongest;
  enc.factory = v::kFactoryVlp16;

  // Quantised block azimuths and the gaps the decoder will interpolate with.
  int count[v::kBlocksPerPacket];
  for (int b = 0; b < v::kBlocksPerPacket; ++b)
    count[b] = v::azimuth_to_count(azimuth_at_offset(t0 + b * v::kBlockPeriodUs));
  double gap_deg[v::kBlocksPerPacket];
  sensing::column_gaps(count, v::kBlocksPerPacket, 1, gap_deg);

  WorldSnapshot snap;
  for (int b = 0; b < v::kBlocksPerPacket; ++b) {
    auto& block = enc.blocks[static_cast<size_t>(b)];
    block.azimuth_deg = count[b] * v::kAzimuthUnitDeg;
    for (int s = 0; s < v::kSequencesPerBlock; ++s) {
      // One snapshot per firing sequence: within its 55 us the robot moves
      // at most a few hundredths of a millimetre.
      const double sequence_us = t0 + v::firing_offset_us(b, s, 0);
      world(start_us_ + std::llround(sequence_us), &snap);
      const int64_t revolution = revolution_at(sequence_us);
      returns_.reach(revolution);
      const double cos_yaw = std::cos(snap.robot.yaw), sin_yaw = std::sin(snap.robot.yaw);
      for (int l = 0; l < v::kLasers; ++l) {
        double within_block_us = s * v::kSequencePeriodUs + l * v::kFiringIntervalUs;
        double az = block.azimuth_deg + gap_deg[b] * within_block_us / v::kBlockPeriodUs;
        Ray ray = laser_ray(snap.robot, cos_yaw, sin_yaw, l, az);
        double range = hit_ground(ray);
        bool ground = true;
        size_t hit = 0;
        for (size_t i = 0; i < snap.solids.size(); ++i) {
          double t = hit_solid(ray, snap.solids[i]);
          if (t < range) {
            range = t;
            ground = false;
            hit = i;
          }
        }
        double distance = 0.0;  // no return
        if (range <= p_.max_range_m) {
          if (!ground) returns_.add(revolution, hit);
          distance = range + (p_.range_noise_std_m > 0.0 ? p_.range_noise_std_m * noise_(rng_) : 0.0);
          if (distance < v::kDistanceUnitM) distance = 0.0;  // noise cannot make a negative range
        }
        block.distance_m[s][l] = distance;
        block.reflectivity[s][l] = ground ? p_.ground_reflectivity : p_.obstacle_reflectivity;
      }
    }
  }
  ++next_packet_;
  return Packet::of(enc.encode(), LidarPort::kData);
}

}  // namespace evade::sim
