// The simulated LiDARs. `LidarSimulator` is what the sim core drives: a
// stream of packets, each complete at a known time, from a model picked by
// the scenario's `lidar.model` (make_lidar_simulator). Vlp16Simulator is
// below; RsHeliosSimulator in rs_helios_sim.h.
//
// The simulated Velodyne VLP-16: casts every firing of the real sensor
// (16 lasers 2.304 us apart, a firing sequence every 55.296 us, 24
// sequences per packet, so 753.5 packets/s) into the world as it is at that
// firing's time, seen from the robot's pose at that time, and encodes the
// ranges into real 1206-byte data packets with lib/sensing's encoder.
//
// Exact agreement with the decoder: the block azimuths are quantised to
// the packet's 0.01 degree before casting, and each laser is cast along the
// azimuth the decoder will interpolate for it (block azimuth + gap to the
// next block times the firing's share of the block time), from the beam
// origin the decoder assumes (dz(laser) on the sensor's z axis). What the
// decoder returns is then on the true surface up to the 2 mm range unit
// and the configured range noise.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "sensing/vlp16.h"
#include "sim/raycast.h"
#include "sim/return_counter.h"
#include "sim/scenario.h"

namespace evade::sim {

struct LidarSimParams {
  double rate_hz = 10.0;           // rotation rate (scenario lidar.rate_hz)
  double range_noise_std_m = 0.0;  // scenario lidar.range_noise_std
  double max_range_m = 100.0;      // beyond: no return (zero distance)
  // Sensor pose on the base: x, y, yaw, roll, pitch from the robot
  // configuration (lidar.mount), height above the ground from the scenario.
  double mount_x_m = 0.0, mount_y_m = 0.0, mount_height_m = 0.5;
  double mount_roll_rad = 0.0, mount_pitch_rad = 0.0, mount_yaw_rad = 0.0;
  uint64_t noise_seed = 1;
  uint8_t ground_reflectivity = 20;
  uint8_t obstacle_reflectivity = 100;
};

// The world at one instant, as the LiDAR needs it.
struct WorldSnapshot {
  Pose2 robot;
  std::vector<Solid> solids;
};
using WorldAt = std::function<void(int64_t utime, WorldSnapshot* out)>;

// One UDP payload and the sensor port it goes to: kData is the VLP-16's
// data port or the RS-Helios MSOP port, kDifop the RS-Helios DIFOP port.
enum class LidarPort { kData, kDifop };
struct Packet {
  static constexpr size_t kMaxSize = 1248;  // the larger of the two models' payloads
  LidarPort port = LidarPort::kData;
  size_t length = 0;
  std::array<uint8_t, kMaxSize> bytes{};
  const uint8_t* data() const { return bytes.data(); }
  size_t size() const { return length; }
  const uint8_t* begin() const { return bytes.data(); }
  const uint8_t* end() const { return bytes.data() + length; }
  template <size_t N>
  static Packet of(const std::array<uint8_t, N>& b, LidarPort port) {
    static_assert(N <= kMaxSize, "packet too large");
    Packet p;
    p.port = port;
    p.length = N;
    std::copy(b.begin(), b.end(), p.bytes.begin());
    return p;
  }
  bool operator==(const Packet& o) const {
    return port == o.port && length == o.length && std::equal(begin(), end(), o.begin());
  }
};

// A simulated sensor: the packets it sends, in order, each built when due.
class LidarSimulator {
 public:
  virtual ~LidarSimulator() = default;
  // The next packet is complete (data: its last firing done) at this time.
  virtual int64_t next_packet_ready_us() const = 0;
  // Builds the next packet, casting against world(t) at each firing's time.
  virtual Packet make_packet(const WorldAt& world) = 0;
  // Drops the next packet unbuilt (the sender fell behind).
  virtual void skip_packet() = 0;
  virtual int64_t packets_made() const = 0;
  // Returns from each solid of the world (its index in WorldSnapshot::solids)
  // in the last complete revolution of the packets made; -1 each before the
  // first revolution is complete (ReturnCounter).
  virtual std::vector<int32_t> returns_last_revolution(size_t solids) const = 0;
};

// The sensor base -> robot base rotation of a mount (R = Rz(yaw) Ry(pitch) Rx(roll)).
void mount_rotation(const LidarSimParams& p, double r[3][3]);

// "vlp16" or "rs_helios" (the scenario's lidar.model); throws
// std::invalid_argument for any other.
std::unique_ptr<LidarSimulator> make_lidar_simulator(const std::string& model, const LidarSimParams& params,
                                                     int64_t start_us);

class Vlp16Simulator : public LidarSimulator {
 public:
  static constexpr double kPacketPeriodUs =
      sensing::vlp16::kBlocksPerPacket * sensing::vlp16::kBlockPeriodUs;  // 1327.104 us

  // The sweep starts at azimuth 0 at `start_us`.
  Vlp16Simulator(const LidarSimParams& params, int64_t start_us);

  // First firing time of packet k, us after the start (fractional), and
  // the same as an absolute time rounded to the microsecond.
  static double packet_offset_us(int64_t k) { return k * kPacketPeriodUs; }
  int64_t packet_start_us(int64_t k) const { return start_us_ + std::llround(packet_offset_us(k)); }
  // The next packet is complete (its last firing done) at this time.
  int64_t next_packet_ready_us() const override;
  int64_t packets_made() const override { return next_packet_; }

  // Builds the next packet: every firing cast against world(t) at its time.
  Packet make_packet(const WorldAt& world) override;
  // Drops the next packet unbuilt (the sender fell behind).
  void skip_packet() override;

  std::vector<int32_t> returns_last_revolution(size_t solids) const override { return returns_.last_complete(solids); }

  // Sensor azimuth (deg, [0, 360)) `offset_us` after the start.
  double azimuth_at_offset(double offset_us) const;

  // Sensor frame of one firing in the world, for tests and for make_packet:
  // the ray of `laser` at (decoder) azimuth `azimuth_deg` from pose `robot`.
  Ray laser_ray(const Pose2& robot, int laser, double azimuth_deg) const;

 private:
  // laser_ray with the robot's heading as (cos, sin), computed once per
  // firing sequence: the sines and cosines were an eighth of a lockstep run.
  Ray laser_ray(const Pose2& robot, double cos_yaw, double sin_yaw, int laser, double azimuth_deg) const;

  LidarSimParams p_;
  int64_t start_us_;
  int64_t next_packet_ = 0;
  std::mt19937_64 rng_;
  std::normal_distribution<double> noise_{0.0, 1.0};
  double mount_rot_[3][3];                                           // sensor -> base rotation (yaw * pitch * roll)
  std::array<double, sensing::vlp16::kLasers> cos_el_{}, sin_el_{};  // of each laser's elevation
  ReturnCounter returns_;
  int64_t revolution_at(double offset_us) const {
    return static_cast<int64_t>(std::floor(p_.rate_hz * offset_us * 1e-6));
  }
};

}  // namespace evade::sim
