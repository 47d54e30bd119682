// The simulated VLP-16 and RS-Helios: packets decoded by lib/sensing's
// decoders (the ones lidar_driver runs) give points on the true surfaces,
// from a standing and from a moving robot; timing, packet rates, azimuth,
// ring elevations and noise are the sensor's.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <string>

#include "sensing/lidar_decoder.h"
#include "sensing/rs_helios.h"
#include "sensing/vlp16.h"
#include "sim/lidar_sim.h"
#include "sim/rs_helios_sim.h"

namespace evade::sim {
namespace {
namespace v = sensing::vlp16;

constexpr int64_t kStartUs = 1'700'000'000'123'456;  // an arbitrary epoch time
constexpr double kCylX = 5.0, kCylY = 1.0, kCylR = 0.25, kCylH = 1.7;
constexpr double kBoxX = -4.0, kBoxY = -3.0, kBoxYaw = 0.4, kBoxL = 2.0, kBoxW = 1.0, kBoxH = 1.0;

std::vector<Solid> world_solids() {
  return {Solid{Shape::kCylinder, kCylX, kCylY, 0.0, kCylR, 0, 0, kCylH},
          Solid{Shape::kBox, kBoxX, kBoxY, kBoxYaw, 0, kBoxL, kBoxW, kBoxH}};
}

// Distance of a world point from the nearest true surface, and which.
enum class Surface { kGround, kCylinder, kBox };
double surface_error(double x, double y, double z, Surface* which) {
  double ground = std::abs(z);
  // Cylinder: side (within height) or top.
  double radial = std::hypot(x - kCylX, y - kCylY);
  double cyl = kNoHit;
  if (z >= -0.01 && z <= kCylH + 0.01) cyl = std::abs(radial - kCylR);
  if (radial <= kCylR + 0.01) cyl = std::min(cyl, std::abs(z - kCylH));
  // Box: distance to the surface of the solid (outside points; on-surface 0).
  double c = std::cos(kBoxYaw), s = std::sin(kBoxYaw);
  double bx = c * (x - kBoxX) + s * (y - kBoxY), by = -s * (x - kBoxX) + c * (y - kBoxY);
  double ex = std::abs(bx) - kBoxL / 2, ey = std::abs(by) - kBoxW / 2, ez = std::abs(z - kBoxH / 2) - kBoxH / 2;
  double box = std::hypot(std::hypot(std::max(ex, 0.0), std::max(ey, 0.0)), std::max(ez, 0.0)) +
               std::min(std::max(ex, std::max(ey, ez)), 0.0);
  box = std::abs(box);
  *which = Surface::kGround;
  double best = ground;
  if (cyl < best) best = cyl, *which = Surface::kCylinder;
  if (box < best) best = box, *which = Surface::kBox;
  return best;
}

struct Decoded {
  v::Return ret;
  double fire_us;  // absolute firing time, from the packet timestamp
};

// Makes `n` packets and decodes them with the driver's decoder.
std::vector<Decoded> run(Vlp16Simulator& sim, int n, const WorldAt& world,
                         std::vector<v::PacketInfo>* infos = nullptr) {
  std::vector<Decoded> out;
  for (int i = 0; i < n; ++i) {
    double start = kStartUs + Vlp16Simulator::packet_offset_us(sim.packets_made());
    Packet p = sim.make_packet(world);
    std::vector<v::Return> rets;
    v::PacketInfo info;
    EXPECT_EQ(v::decode_packet(p.data(), p.size(), v::DecodeOptions{}, &rets, &info), v::PacketStatus::kOk);
    if (infos) infos->push_back(info);
    for (const auto& r : rets) out.push_back(Decoded{r, start + r.time_offset_us});
  }
  return out;
}

LidarSimParams params(double noise) {
  LidarSimParams p;
  p.rate_hz = 10.0;
  p.range_noise_std_m = noise;
  p.mount_height_m = 0.5;
  p.max_range_m = 100.0;
  return p;
}

// Sensor-frame point -> world, for a robot at `pose` (mount: height 0.5 on the base centre).
void to_world(const v::Return& r, const Pose2& pose, double* x, double* y, double* z) {
  double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  *x = pose.x + c * r.x - s * r.y;
  *y = pose.y + s * r.x + c * r.y;
  *z = 0.5 + r.z;
}

TEST(LidarSim, TimingAndAzimuthAreTheSensors) {
  Vlp16Simulator sim(params(0.0), kStartUs);
  EXPECT_NEAR(Vlp16Simulator::kPacketPeriodUs, 1327.104, 1e-9);
  EXPECT_NEAR(1e6 / Vlp16Simulator::kPacketPeriodUs, 753.5, 0.1);  // packets per second
  WorldAt world = [](int64_t, WorldSnapshot* w) {
    w->robot = Pose2{};
    w->solids = world_solids();
  };
  std::vector<v::PacketInfo> infos;
  run(sim, 3, world, &infos);
  for (int i = 0; i < 3; ++i) {
    int64_t first = kStartUs + std::llround(i * 1327.104);
    EXPECT_EQ(infos[static_cast<size_t>(i)].timestamp_us_past_hour, static_cast<uint32_t>(first % 3'600'000'000LL));
    EXPECT_EQ(infos[static_cast<size_t>(i)].return_mode, v::kStrongest);
    EXPECT_EQ(infos[static_cast<size_t>(i)].factory, v::kFactoryVlp16);
  }
  // 10 Hz: 0.199 deg per firing sequence ("0.2 deg azimuth step").
  EXPECT_NEAR(sim.azimuth_at_offset(v::kSequencePeriodUs) - sim.azimuth_at_offset(0.0), 0.1990656, 1e-9);
  // One revolution takes 100 ms.
  EXPECT_NEAR(sim.azimuth_at_offset(50'000.0), 180.0, 1e-9);
  EXPECT_NEAR(sim.azimuth_at_offset(100'000.0 + 27.0), 360.0 * 27e-6 * 10.0, 1e-9);
  EXPECT_EQ(sim.next_packet_ready_us(), kStartUs + 5309);  // 4 * 1327.104 rounded up
}

TEST(LidarSim, StandingRobotPointsLieOnTheTrueSurfaces) {
  Vlp16Simulator sim(params(0.0), kStartUs);
  WorldAt world = [](int64_t, WorldSnapshot* w) {
    w->robot = Pose2{};
    w->solids = world_solids();
  };
  // One full revolution (76 packets > 100 ms / 1.327 ms).
  std::vector<Decoded> pts = run(sim, 76, world);
  int on[3] = {0, 0, 0};
  double worst = 0.0;
  for (const auto& d : pts) {
    double x, y, z;
    to_world(d.ret, Pose2{}, &x, &y, &z);
    Surface which;
    double e = surface_error(x, y, z, &which);
    worst = std::max(worst, e);
    on[static_cast<int>(which)]++;
  }
  // Ranges travel in 2 mm units (1 mm rounding); points are floats.
  EXPECT_LT(worst, 0.0015);
  // The 8 downward lasers see the ground all around (some blocked by the solids).
  EXPECT_GT(on[0], 8 * 1700);
  EXPECT_GT(on[1], 20);  // a 0.5 m wide cylinder at 5.1 m: ~5.6 deg of azimuth, 28 columns
  EXPECT_GT(on[2], 50);
  // Upward lasers see sky: no return. A full revolution is 16 * 1808 firings.
  EXPECT_LT(pts.size(), 16u * 1824u / 2u + 2000u);
}

TEST(LidarSim, MovingRobotEachFiringFromItsOwnPose) {
  // 1 m/s along x, turning at 0.5 rad/s: 10 cm and 3 degrees per revolution.
  auto pose_at = [](double t_us) {
    double t = (t_us - kStartUs) * 1e-6;
    double w = 0.5, vel = 1.0;
    return Pose2{vel / w * std::sin(w * t), vel / w * (1 - std::cos(w * t)), w * t};
  };
  Vlp16Simulator sim(params(0.0), kStartUs);
  WorldAt world = [&](int64_t t, WorldSnapshot* w) {
    w->robot = pose_at(static_cast<double>(t));
    w->solids = world_solids();
  };
  std::vector<Decoded> pts = run(sim, 76, world);
  double worst = 0.0, worst_if_static = 0.0;
  int cyl = 0;
  for (const auto& d : pts) {
    double x, y, z;
    Surface which;
    to_world(d.ret, pose_at(d.fire_us), &x, &y, &z);
    worst = std::max(worst, surface_error(x, y, z, &which));
    cyl += which == Surface::kCylinder;
    // The same point placed with the revolution's first pose is off the surface.
    to_world(d.ret, pose_at(kStartUs), &x, &y, &z);
    worst_if_static = std::max(worst_if_static, surface_error(x, y, z, &which));
  }
  // Firing times are rounded to the microsecond (1 um of motion); ranges to 1 mm.
  EXPECT_LT(worst, 0.0016);
  EXPECT_GT(worst_if_static, 0.05);
  EXPECT_GT(cyl, 20);
}

TEST(LidarSim, RangeNoiseHasTheScenarioStd) {
  const double sigma = 0.02;
  Vlp16Simulator sim(params(sigma), kStartUs);
  WorldAt world = [](int64_t, WorldSnapshot* w) {
    w->robot = Pose2{};
    w->solids = {};
  };
  std::vector<Decoded> pts = run(sim, 76, world);
  // Ground only: the true range of laser l is (0.5 + dz) / sin(-el).
  double sum = 0, sum2 = 0;
  int n = 0;
  for (const auto& d : pts) {
    const v::Laser& l = v::kLaserTable[d.ret.laser];
    ASSERT_LT(l.elevation_deg, 0.0);
    double range = std::sqrt(d.ret.x * d.ret.x + d.ret.y * d.ret.y +
                             (d.ret.z - l.vertical_offset_m) * (d.ret.z - l.vertical_offset_m));
    double truth = (0.5 + l.vertical_offset_m) / std::sin(-l.elevation_deg * M_PI / 180.0);
    double e = range - truth;
    sum += e;
    sum2 += e * e;
    ++n;
  }
  ASSERT_GT(n, 10000);
  double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.001);
  EXPECT_NEAR(sd, sigma, 0.001);
}

TEST(LidarSim, SameSeedSamePackets) {
  WorldAt world = [](int64_t, WorldSnapshot* w) {
    w->robot = Pose2{};
    w->solids = world_solids();
  };
  Vlp16Simulator a(params(0.01), kStartUs), b(params(0.01), kStartUs);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(a.make_packet(world), b.make_packet(world));
}

// ------------------------------------------------------------ RS-Helios
namespace h = sensing::rs_helios;

struct HeliosDecoded {
  sensing::LidarReturn ret;
  double fire_us;  // absolute firing time, from the packet's UTC header time
};

// Runs the simulator until `until_us`, decoding every packet as the driver
// does (nothing before the first DIFOP). Counts packets by kind.
struct HeliosRun {
  std::vector<HeliosDecoded> points;
  std::vector<int64_t> difop_ready_us, msop_utc_us;
  h::Calibration cal;
  bool have_cal = false;
};
HeliosRun run_helios(RsHeliosSimulator& sim, int64_t until_us, const WorldAt& world) {
  HeliosRun r;
  int64_t last_ready = 0;
  while (sim.next_packet_ready_us() <= until_us) {
    const int64_t ready = sim.next_packet_ready_us();
    EXPECT_GE(ready, last_ready);  // packets come out in time order
    last_ready = ready;
    Packet p = sim.make_packet(world);
    EXPECT_EQ(p.size(), h::kPacketSize);
    if (p.port == LidarPort::kDifop) {
      EXPECT_EQ(h::classify(p.data(), p.size()), h::PacketKind::kDifop);
      EXPECT_EQ(h::parse_difop(p.data(), p.size(), &r.cal), h::PacketStatus::kOk);
      r.have_cal = true;
      r.difop_ready_us.push_back(ready);
      continue;
    }
    EXPECT_EQ(h::classify(p.data(), p.size()), h::PacketKind::kMsop);
    if (!r.have_cal) continue;
    std::vector<sensing::LidarReturn> rets;
    h::PacketInfo info;
    EXPECT_EQ(h::decode_msop(p.data(), p.size(), r.cal, {}, &rets, &info), h::PacketStatus::kOk);
    r.msop_utc_us.push_back(info.utc_us);
    for (const auto& ret : rets)
      r.points.push_back(
          HeliosDecoded{ret, static_cast<double>(info.utc_us) + static_cast<double>(ret.time_offset_us)});
  }
  return r;
}

void helios_to_world(const sensing::LidarReturn& r, const Pose2& pose, double height, double* x, double* y, double* z) {
  double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  *x = pose.x + c * r.x - s * r.y;
  *y = pose.y + s * r.x + c * r.y;
  *z = height + r.z;
}

TEST(RsHeliosSim, PacketRatesAreTheSensors) {
  RsHeliosSimulator sim(params(0.0), kStartUs);
  EXPECT_NEAR(RsHeliosSimulator::kPacketPeriodUs, 666.72, 1e-9);
  EXPECT_NEAR(1e6 / RsHeliosSimulator::kPacketPeriodUs, 1499.88, 0.01);
  WorldAt world = [](int64_t, WorldSnapshot* w) {
    w->robot = Pose2{};
    w->solids = {};
  };
  // 3 s of packets: a DIFOP at the start and every second after, MSOPs every 666.72 us.
  HeliosRun r = run_helios(sim, kStartUs + 3'000'000, world);
  ASSERT_EQ(r.difop_ready_us.size(), 4u);
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(r.difop_ready_us[i], kStartUs + static_cast<int64_t>(i) * 1'000'000);
  EXPECT_EQ(sim.difop_made(), 4);
  EXPECT_EQ(sim.msop_made(), 4499);  // floor(3e6 / 666.72) packets complete by then
  ASSERT_EQ(r.msop_utc_us.size(), 4499u);
  for (size_t k = 0; k < r.msop_utc_us.size(); ++k)
    EXPECT_EQ(r.msop_utc_us[k], kStartUs + std::llround(k * 666.72)) << k;
  EXPECT_EQ(r.cal.rpm, 600);
  EXPECT_EQ(r.cal.return_mode, h::kStrongest);
}

TEST(RsHeliosSim, RingElevationsAreTheHelios5515s) {
  RsHeliosSimulator sim(params(0.0), kStartUs);
  WorldAt world = [](int64_t, WorldSnapshot* w) {
    w->robot = Pose2{};
    w->solids = {};
  };
  HeliosRun r = run_helios(sim, kStartUs + 110'000, world);
  ASSERT_TRUE(r.have_cal);
  // The DIFOP carries the nominal table: +15 deg (channel 1) to -55 deg
  // (channel 32), 70 deg of vertical field of view, 1.33 deg apart at the horizon.
  EXPECT_DOUBLE_EQ(r.cal.vertical_deg[0], 15.0);
  EXPECT_DOUBLE_EQ(r.cal.vertical_deg[31], -55.0);
  for (int c = 0; c < h::kChannels; ++c) {
    EXPECT_NEAR(r.cal.vertical_deg[c], RsHeliosSimulator::kElevationDeg[static_cast<size_t>(c)], 1e-9);
    EXPECT_NEAR(r.cal.horizontal_deg[c], (c % 2 == 0) ? -4.0 : 4.0, 1e-9);
  }
  EXPECT_EQ(r.cal.ring[31], 0);   // lowest
  EXPECT_EQ(r.cal.ring[0], 31);   // highest
  EXPECT_EQ(r.cal.ring[17], 13);  // -16 deg fires before -13 deg: rings follow elevation, not channel order
  EXPECT_EQ(r.cal.ring[18], 14);
  // Every downward channel sees the flat ground at the elevation it claims:
  // z / horizontal distance = tan(elevation), from the sensor 0.5 m up.
  int per_channel[h::kChannels] = {};
  for (const auto& d : r.points) {
    const int c = d.ret.laser;
    ASSERT_LT(RsHeliosSimulator::kElevationDeg[static_cast<size_t>(c)], 0.0) << "an upward channel hit the ground";
    EXPECT_NEAR(d.ret.z, -0.5, 0.002);
    const double horizontal =
        std::hypot(d.ret.x - h::kOpticalCentreOffsetM * std::cos(d.ret.firing_azimuth_deg * M_PI / 180),
                   d.ret.y + h::kOpticalCentreOffsetM * std::sin(d.ret.firing_azimuth_deg * M_PI / 180));
    EXPECT_NEAR(std::atan2(d.ret.z, horizontal) * 180 / M_PI, RsHeliosSimulator::kElevationDeg[static_cast<size_t>(c)],
                0.2);
    per_channel[c]++;
  }
  for (int c = 0; c < h::kChannels; ++c) {
    if (RsHeliosSimulator::kElevationDeg[static_cast<size_t>(c)] < 0.0)
      EXPECT_GT(per_channel[c], 1700) << c;  // about 1800 firings a revolution at 10 Hz
    else
      EXPECT_EQ(per_channel[c], 0) << c;
  }
}

TEST(RsHeliosSim, StandingAndMovingRobotPointsLieOnTheTrueSurfaces) {
  auto pose_at = [](double t_us) {  // 1 m/s, turning at 0.5 rad/s
    double t = (t_us - kStartUs) * 1e-6;
    return Pose2{2.0 * std::sin(0.5 * t), 2.0 * (1 - std::cos(0.5 * t)), 0.5 * t};
  };
  for (bool moving : {false, true}) {
    LidarSimParams p = params(0.0);
    p.mount_height_m = 0.8;
    RsHeliosSimulator sim(p, kStartUs);
    WorldAt world = [&](int64_t t, WorldSnapshot* w) {
      w->robot = moving ? pose_at(static_cast<double>(t)) : Pose2{};
      w->solids = world_solids();
    };
    HeliosRun r = run_helios(sim, kStartUs + 105'000, world);  // one revolution after the DIFOP
    int on[3] = {0, 0, 0};
    double worst = 0.0, worst_if_static = 0.0;
    for (const auto& d : r.points) {
      double x, y, z;
      Surface which;
      helios_to_world(d.ret, moving ? pose_at(d.fire_us) : Pose2{}, 0.8, &x, &y, &z);
      worst = std::max(worst, surface_error(x, y, z, &which));
      on[static_cast<int>(which)]++;
      helios_to_world(d.ret, Pose2{}, 0.8, &x, &y, &z);
      worst_if_static = std::max(worst_if_static, surface_error(x, y, z, &which));
    }
    // 2.5 mm distance unit (1.25 mm rounding), float points, 1 us firing-time rounding.
    EXPECT_LT(worst, 0.002) << (moving ? "moving" : "standing");
    if (moving) {
      EXPECT_GT(worst_if_static, 0.05);
    }
    EXPECT_GT(on[0], 21 * 1700);  // 22 of the 32 channels look down, about 1880 firings each, some hidden
    EXPECT_GT(on[1], 50);
    EXPECT_GT(on[2], 100);
  }
}

TEST(RsHeliosSim, RevolutionsThroughTheDriversDecoder) {
  LidarSimParams p = params(0.01);
  RsHeliosSimulator sim(p, kStartUs);
  WorldAt world = [](int64_t, WorldSnapshot* w) {
    w->robot = Pose2{};
    w->solids = {};
  };
  sensing::LidarDecoderParams dp;
  dp.model = sensing::LidarModel::kRsHelios;
  dp.min_range_m = 0.0;
  dp.max_range_m = 200.0;
  dp.self_filter = false;
  std::map<std::string, int64_t> counts;
  sensing::LidarDecoder dec(dp, [&](const std::string& k, int64_t n) { counts[k] += n; });
  std::vector<sensing::Revolution> revs;
  while (sim.next_packet_ready_us() <= kStartUs + 1'000'000) {
    const int64_t t = sim.next_packet_ready_us();
    Packet pk = sim.make_packet(world);
    dec.feed(pk.data(), pk.size(), t, &revs);
  }
  // 10 revolutions in a second (the sweep starts at 0 deg, the cut angle).
  ASSERT_GE(revs.size(), 9u);
  for (size_t i = 1; i + 1 < revs.size(); ++i) {
    const auto& c = revs[i].cloud;
    EXPECT_EQ(c.sensor_model, "rs_helios");
    EXPECT_NEAR(c.packets, 150, 1);  // 100 ms / 666.72 us
    EXPECT_GT(c.n, 22 * 1790);       // the 22 downward channels, 1800 firings each
    std::set<int> rings(c.ring.begin(), c.ring.end());
    EXPECT_EQ(rings.size(), 22u);  // the downward rings 0..21 (flat ground, nothing else)
    EXPECT_EQ(*rings.begin(), 0);
    EXPECT_EQ(*rings.rbegin(), 21);
  }
  EXPECT_EQ(counts["malformed_bad_header"], 0);
}

// A tilted, offset mount (looking 0.3 rad down, turned 0.5 rad, 0.2 m
// forward) at 20 Hz: the decoded points, put through the mount pose, still
// lie on the true surfaces; 20 revolutions a second, rpm 1200 in the DIFOP.
TEST(RsHeliosSim, TiltedMountAt20HzPointsLieOnTheTrueSurfaces) {
  LidarSimParams p = params(0.0);
  p.rate_hz = 20.0;
  p.mount_height_m = 0.9;
  p.mount_x_m = 0.2;
  p.mount_pitch_rad = 0.3;
  p.mount_yaw_rad = 0.5;
  p.mount_roll_rad = 0.05;
  RsHeliosSimulator sim(p, kStartUs);
  WorldAt world = [](int64_t, WorldSnapshot* w) {
    w->robot = Pose2{};
    w->solids = world_solids();
  };
  HeliosRun r = run_helios(sim, kStartUs + 1'000'000, world);
  EXPECT_EQ(r.cal.rpm, 1200);
  double rot[3][3];
  mount_rotation(p, rot);
  double worst = 0.0;
  int on[3] = {0, 0, 0};
  for (const auto& d : r.points) {
    const double s[3] = {d.ret.x, d.ret.y, d.ret.z};
    double b[3];
    for (int i = 0; i < 3; ++i) b[i] = rot[i][0] * s[0] + rot[i][1] * s[1] + rot[i][2] * s[2];
    Surface which;
    worst = std::max(worst, surface_error(b[0] + 0.2, b[1], b[2] + 0.9, &which));
    on[static_cast<int>(which)]++;
  }
  EXPECT_LT(worst, 0.002);
  EXPECT_GT(on[1], 100);
  EXPECT_GT(on[2], 100);
  sensing::LidarDecoderParams dp;
  dp.model = sensing::LidarModel::kRsHelios;
  dp.min_range_m = 0.0;
  dp.max_range_m = 200.0;
  dp.self_filter = false;
  sensing::LidarDecoder dec(dp, nullptr);
  std::vector<sensing::Revolution> revs;
  RsHeliosSimulator again(p, kStartUs);
  while (again.next_packet_ready_us() <= kStartUs + 1'000'000) {
    const int64_t t = again.next_packet_ready_us();
    Packet pk = again.make_packet(world);
    dec.feed(pk.data(), pk.size(), t, &revs);
  }
  EXPECT_EQ(revs.size(), 19u);  // 20 a second; the 20th is complete when the next one starts
  for (size_t i = 0; i < revs.size(); ++i) EXPECT_NEAR(revs[i].cloud.packets, 75, 1) << i;  // 50 ms / 666.72 us
}

}  // namespace
}  // namespace evade::sim
