#include "process_replay.h"

#include <algorithm>
#include <cstdlib>
#include <memory>

#include "bus/auth.h"
#include "bus/core.h"
#include "bus/log_replay.h"
#include "evade/pointcloud_t.hpp"
#include "mapping/elevation_map_core.h"
#include "planning/planner_core.h"
#include "prediction/predictor_core.h"
#include "sensing/lidar_driver_core.h"
#include "tracking/tracker_core.h"

namespace evade::replay {
namespace {

bus::DiffOptions tolerances(double abs_tol, double rel_tol) {
  bus::DiffOptions d;
  d.default_tolerance = {abs_tol, rel_tol};
  return d;
}

std::vector<bus::LogEvent> only(const std::vector<bus::LogEvent>& in, const std::vector<std::string>& channels) {
  std::vector<bus::LogEvent> out;
  for (const auto& e : in)
    if (std::find(channels.begin(), channels.end(), e.channel) != channels.end()) out.push_back(e);
  return out;
}

// `keys`: the core signs and checks the authenticated channels as it does
// live (the golden inputs are signed with the test key, test/data/bus_test.key).
std::vector<bus::LogEvent> run_core(bus::Core& core, const std::vector<bus::LogEvent>& in,
                                    const bus::AuthSetup* keys = nullptr) {
  std::unique_ptr<bus::HmacAuth> auth;
  if (keys) {
    auth = keys->make(core.name());
    core.set_authenticator(auth.get());
  }
  bus::ReplayOptions opt;
  opt.keep_health = false;
  return bus::replay({&core}, in, opt);
}

std::vector<bus::LogEvent> decode_scans(const std::vector<bus::LogEvent>& input, const config::Node& root) {
  auto core = sensing::LidarDriverCore::from_config(root, sensing::LidarDriverCore::Source::kScans);
  return run_core(*core, only(input, {"LIDAR_SCAN"}));
}

// Stable merge by timestamp: the inputs of one process from two sources.
std::vector<bus::LogEvent> merge(std::vector<bus::LogEvent> a, const std::vector<bus::LogEvent>& b) {
  a.insert(a.end(), b.begin(), b.end());
  std::stable_sort(a.begin(), a.end(), [](const auto& x, const auto& y) { return x.timestamp < y.timestamp; });
  return a;
}

void thin_points(std::vector<bus::LogEvent>* events) {
  for (auto& e : *events) {
    if (e.channel != "LIDAR_POINTS") continue;
    evade::pointcloud_t pc;
    if (!bus::decode(e.data.data(), e.data.size(), &pc)) continue;
    evade::pointcloud_t t = pc;
    t.x.clear();
    t.y.clear();
    t.z.clear();
    t.intensity.clear();
    t.ring.clear();
    t.time_offset.clear();
    for (int i = 0; i < pc.n; i += kPointStride) {
      t.x.push_back(pc.x[i]);
      t.y.push_back(pc.y[i]);
      t.z.push_back(pc.z[i]);
      t.intensity.push_back(pc.intensity[i]);
      t.ring.push_back(pc.ring[i]);
      t.time_offset.push_back(pc.time_offset[i]);
    }
    t.n = static_cast<int32_t>(t.x.size());
    e.data = bus::encode(t);
  }
}

// The golden logs are signed with the committed test-only key: that key,
// unless $EVADE_BUS_KEY names another (its file's mode is not checked: the
// key is public and signs nothing but test data).
bus::AuthSetup golden_keys(const config::Node& root) {
  if (std::getenv("EVADE_BUS_KEY")) return bus::load_auth(root);
  bus::AuthSetup keys;
  keys.key = bus::load_key(std::string(EVADE_SOURCE_DIR) + "/test/data/bus_test.key", /*owner_only=*/false);
  keys.window_s = bus::AuthParams::from_config(root).window_s;
  return keys;
}

}  // namespace

const std::vector<ProcessCase>& process_cases() {
  // Tolerances: the replay is deterministic, so on one machine the outputs
  // are bit-identical; the tolerances absorb only floating-point
  // differences between compilers or CPUs (libm, fused multiply-add):
  // 1 um on geometry and 1e-9 relative elsewhere.
  static const std::vector<ProcessCase> cases = [] {
    std::vector<ProcessCase> c;
    c.push_back({"lidar_driver",
                 {"LIDAR_SCAN"},
                 tolerances(1e-6, 1e-9),
                 "LIDAR_SCAN packets decoded again; LIDAR_POINTS compared (every 64th point)"});
    c.push_back({"elevation_map",
                 {"LIDAR_SCAN", "ODOMETRY"},
                 tolerances(1e-6, 1e-9),
                 "points decoded from LIDAR_SCAN + logged ODOMETRY; ELEVATION_MAP compared"});
    c.push_back({"tracker", {"ELEVATION_MAP"}, tolerances(1e-6, 1e-9), "logged ELEVATION_MAP; OBSTACLES compared"});
    // An authentication code is a function of the rest of the message: a
    // difference within the tolerances changes it entirely, so it is not compared.
    ProcessCase predictor{"predictor",
                          {"OBSTACLES", "OCCLUSIONS"},
                          tolerances(1e-6, 1e-9),
                          "logged OBSTACLES, OCCLUSIONS; OBSTACLE_PREDICTIONS compared"};
    predictor.diff.ignore_fields = {"OBSTACLE_PREDICTIONS.auth_mac"};
    c.push_back(predictor);
    // The planner's outputs come out of an iterative solver: a last-bit
    // difference can move an iterate, so its tolerance is 1 mm / 1 mrad;
    // solve_time_us is wall time and never compared.
    ProcessCase planner{
        "planner",
        {"ODOMETRY", "ROUTE", "OBSTACLES", "OBSTACLE_PREDICTIONS", "OCCLUSIONS"},
        tolerances(1e-3, 1e-6),
        "logged ODOMETRY, ROUTE, OBSTACLES, OBSTACLE_PREDICTIONS, OCCLUSIONS; PLAN and CMD_VEL compared"};
    planner.diff.ignore_fields = {"PLAN.solve_time_us", "CMD_VEL.auth_mac"};
    c.push_back(planner);
    return c;
  }();
  return cases;
}

std::vector<bus::LogEvent> run_process(const ProcessCase& pc, const std::vector<bus::LogEvent>& input,
                                       const config::Node& root) {
  std::vector<bus::LogEvent> out;
  const bus::AuthSetup keys = golden_keys(root);
  if (pc.process == "lidar_driver") {
    out = decode_scans(input, root);
    thin_points(&out);
  } else if (pc.process == "elevation_map") {
    auto points = decode_scans(input, root);
    auto core = mapping::ElevationMapCore::from_config(root);
    out = run_core(*core, merge(points, only(input, {"ODOMETRY"})), &keys);
  } else if (pc.process == "tracker") {
    auto core = tracking::TrackerCore::from_config(root);
    out = run_core(*core, only(input, pc.inputs), &keys);
  } else if (pc.process == "predictor") {
    auto core = prediction::PredictorCore::from_config(root);
    out = run_core(*core, only(input, pc.inputs), &keys);
  } else if (pc.process == "planner") {
    auto core = planning::PlannerCore::from_config(root);
    out = run_core(*core, only(input, pc.inputs), &keys);
  } else {
    throw std::runtime_error("process-replay: unknown process " + pc.process);
  }
  return out;
}

std::vector<bus::LogEvent> cut_case(const std::vector<bus::LogEvent>& run, double start_s, double duration_s,
                                    const std::vector<std::string>& channels) {
  std::vector<bus::LogEvent> out;
  if (run.empty()) return out;
  const int64_t t0 = run.front().timestamp + static_cast<int64_t>(start_s * 1e6);
  const int64_t t1 = t0 + static_cast<int64_t>(duration_s * 1e6);
  const bus::LogEvent* route = nullptr;
  for (const auto& e : run) {
    if (e.timestamp < t0) {
      if (e.channel == "ROUTE") route = &e;
      continue;
    }
    if (e.timestamp >= t1) break;
    if (route) {
      bus::LogEvent r = *route;
      r.timestamp = e.timestamp;
      out.push_back(r);
      route = nullptr;
    }
    if (std::find(channels.begin(), channels.end(), e.channel) != channels.end()) out.push_back(e);
  }
  return out;
}

}  // namespace evade::replay
