// evade-viz: a 3D view of what the robot sees and plans (PCL visualizer).
//
//   evade-viz [--config F] [--lcm-url U]                 live, on the bus
//   evade-viz --log RUN.lcmlog [--at S] [--speed X] [--paused]
//                                                         a log, from S seconds in
//   evade-viz --log RUN.lcmlog --at S --snapshot F.png    one frame to a PNG, no interaction
//   evade-viz --at S --snapshot F.png                     live: the frame after listening S seconds
//   evade-viz --log RUN.lcmlog --snapshot-moments DIR     a simulated run's key frames (moments.h):
//                                                         DIR/viz_obstacle_<id>.png at each obstacle's
//                                                         first sight, DIR/viz_closest.png
//
// Layers, keys and colours: scene.h, playback.h. Without LIDAR_POINTS on
// the bus or in the log, LIDAR_SCAN is decoded (the configured LiDAR).
#include <sys/stat.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <memory>

#include "bus/live_bus.h"
#include "bus/log.h"
#include "bus/process_main.h"
#include "moments.h"
#include "playback.h"
#include "render.h"

namespace {

constexpr const char* kName = "evade-viz";
using evade::viz::Controls;
using evade::viz::Renderer;
using evade::viz::VizParams;
using evade::viz::WorldState;

double wall_s() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

void frame(Renderer& r, const WorldState& w, const Controls& c, const VizParams& p, const std::string& status) {
  const auto scene = evade::viz::build_scene(w, c.layers, p);
  r.draw(scene, status);
  if (c.follow) r.follow(scene);
}

// The robot.yaml beside a run log (run_scenario and tools/launch write the
// effective one there: the scenario's LiDAR mount decodes LIDAR_SCAN right),
// when it has a viz section (one written before evade-viz existed has not);
// else "" (the default configuration).
std::string config_beside(const std::string& log) {
  const auto beside = std::filesystem::path(log).parent_path() / "robot.yaml";
  if (!std::filesystem::exists(beside)) return "";
  try {
    if (evade::config::load_file(beside.string()).has("viz")) return beside.string();
  } catch (const evade::config::ConfigError&) {
    return beside.string();  // let the strict load report it
  }
  std::fprintf(stderr, "%s: %s has no viz section (written before evade-viz): using the default configuration\n", kName,
               beside.c_str());
  return "";
}

bool written(const std::string& png) {
  struct stat st;
  if (::stat(png.c_str(), &st) == 0 && st.st_size > 0) return true;
  std::fprintf(stderr, "%s: %s was not written\n", kName, png.c_str());
  return false;
}

// Live; with a non-empty `png`, listens `at` seconds, writes one frame and returns.
int run_live(const std::string& url, WorldState& w, const VizParams& p, double at, const std::string& png) {
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    std::fprintf(stderr, "%s: cannot start LCM on %s\n", kName, url.c_str());
    return 1;
  }
  struct Handler {
    WorldState* w;
    void on(const lcm::ReceiveBuffer* rb, const std::string& ch) {
      w->apply(ch, static_cast<const uint8_t*>(rb->data), rb->data_size, rb->recv_utime);
    }
  } handler{&w};
  // The channels WorldState draws (and HEALTH is not one of them).
  using evade::sensing::kLidarPointsChannel;
  using evade::sensing::kLidarScanChannel;
  lcm.subscribe("ODOMETRY", &Handler::on, &handler);
  lcm.subscribe("ELEVATION_MAP", &Handler::on, &handler);
  lcm.subscribe("OBSTACLES", &Handler::on, &handler);
  lcm.subscribe("OBSTACLE_PREDICTIONS", &Handler::on, &handler);
  lcm.subscribe("PLAN", &Handler::on, &handler);
  lcm.subscribe("ROUTE", &Handler::on, &handler);
  lcm.subscribe("SIM_TRUTH", &Handler::on, &handler);
  lcm.subscribe(kLidarPointsChannel, &Handler::on, &handler);
  lcm.subscribe(kLidarScanChannel, &Handler::on, &handler);
  Renderer r(p);
  Controls c;
  r.on_key([&](const std::string& k) { c.on_key(k, p.seek_step_s); });
  const auto& stop = evade::bus::stop_on_signals();
  const double shot_at = wall_s() + at;
  for (double next = wall_s(); !stop.load();) {
    lcm.handleTimeout(5);
    if (wall_s() < next) continue;
    next = wall_s() + p.refresh_period_s;
    frame(r, w, c, p, "live on " + url + "  (keys: k camera, z m t y n b i v layers)");
    if (!png.empty() && wall_s() >= shot_at) {
      r.snapshot(png);
      if (!written(png)) return 1;
      std::fprintf(stderr, "%s: %s after %.1f s live (%zu cloud points, %lld malformed)\n", kName, png.c_str(), at,
                   w.cloud.size(), static_cast<long long>(w.malformed()));
      return 0;
    }
    if (!r.spin(1)) break;
  }
  return 0;
}

int run_log(evade::viz::LogTimeline& t, WorldState& w, const VizParams& p, double at, double speed, bool paused) {
  Renderer r(p);
  Controls c;
  c.speed = speed;
  c.paused = paused;
  r.on_key([&](const std::string& k) { c.on_key(k, p.seek_step_s); });
  t.seek(&w, at);
  const auto& stop = evade::bus::stop_on_signals();
  for (double last = wall_s(); !stop.load();) {
    const double now = wall_s();
    if (c.seek_to_start || c.seek_by_s != 0.0) {
      t.seek(&w, c.seek_to_start ? 0.0 : t.position_s() + c.seek_by_s);
      c.seek_to_start = false;
      c.seek_by_s = 0.0;
    } else if (c.steps > 0) {
      t.advance(&w, p.refresh_period_s);
      --c.steps;
    } else if (!c.paused) {
      t.advance(&w, (now - last) * c.speed);
    }
    last = now;
    frame(r, w, c, p, c.status(t.position_s(), t.duration_s()));
    if (!r.spin(int(p.refresh_period_s * 1000))) break;
  }
  return 0;
}

int snapshot(evade::viz::LogTimeline& t, WorldState& w, const VizParams& p, double at, const std::string& png) {
  Renderer r(p);
  Controls c;
  t.seek(&w, at);
  frame(r, w, c, p, c.status(t.position_s(), t.duration_s()));
  r.snapshot(png);
  if (!written(png)) return 1;
  std::fprintf(stderr, "%s: %s at %.2f s of %.2f s (%zu cloud points)\n", kName, png.c_str(), t.position_s(),
               t.duration_s(), w.cloud.size());
  return 0;
}

int snapshot_moments(evade::viz::LogTimeline& t, WorldState& w, const VizParams& p,
                     const std::vector<evade::viz::Moment>& moments, const std::string& dir) {
  Renderer r(p);
  Controls c;
  for (const auto& m : moments) {
    const std::string png = dir + "/viz_" + m.name + ".png";
    t.seek(&w, m.t_s);
    frame(r, w, c, p, m.name + ": " + c.status(t.position_s(), t.duration_s()));
    r.snapshot(png);
    if (!written(png)) return 1;
    std::fprintf(stderr, "%s: %s at %.2f s\n", kName, png.c_str(), t.position_s());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"evade-viz: what the robot sees and plans, live or from a log"};
  evade::bus::CommonOptions opts;
  evade::bus::add_robot_options(app, opts, false);  // --config (default: the robot.yaml beside --log's log), --robot
  app.add_option("--lcm-url", opts.lcm_url, "LCM URL (default $LCM_DEFAULT_URL, else host-local)");
  std::string log, png;
  double at = 0.0, speed = 1.0;
  bool paused = false;
  auto* log_opt = app.add_option("--log", log, "play this lcm-logger log instead of listening");
  app.add_option("--at", at, "start this many seconds into the log (live with --snapshot: after listening this long)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--speed", speed, "playback speed")->needs(log_opt)->check(CLI::PositiveNumber);
  app.add_flag("--paused", paused, "start paused")->needs(log_opt);
  auto* png_opt = app.add_option("--snapshot", png, "render the frame at --at to this PNG and exit");
  std::string moments_dir;
  app.add_option("--snapshot-moments", moments_dir,
                 "write DIR/viz_obstacle_<id>.png (first sight) and DIR/viz_closest.png of a simulated run, exit")
      ->needs(log_opt)
      ->excludes(png_opt);
  CLI11_PARSE(app, argc, argv);

  if (opts.config_path.empty() && !log.empty()) opts.config_path = config_beside(log);
  const evade::config::Node root = evade::bus::load_config_or_exit(kName, opts);
  VizParams p;
  std::unique_ptr<WorldState> w;
  try {
    p = VizParams::from_config(root);
    w = std::make_unique<WorldState>(evade::sensing::LidarDriverParams::from_config(root),
                                     evade::mapping::ElevationMapParams::from_config(root.section("elevation_map")));
  } catch (const evade::config::ConfigError& e) {
    std::fprintf(stderr, "%s: %s\n", kName, e.what());
    return 2;
  }
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display) {
    std::fprintf(stderr,
                 "%s: no display (DISPLAY is unset); without one run it under Xvfb: "
                 "xvfb-run -a -s \"-screen 0 %dx%dx24\" %s ...\n",
                 kName, p.window_width_px, p.window_height_px, argv[0]);
    return 2;
  }
  try {
    if (log.empty())
      return run_live(opts.lcm_url.empty() ? evade::bus::default_lcm_url() : opts.lcm_url, *w, p, at, png);
    auto events = evade::bus::read_log(log);
    if (events.empty()) {
      std::fprintf(stderr, "%s: %s holds no events (not an lcm-logger log?)\n", kName, log.c_str());
      return 1;
    }
    std::vector<evade::viz::Moment> moments;
    if (!moments_dir.empty())
      moments = evade::viz::key_moments(events, evade::metrics::MetricsParams::from_config(root.section("metrics")));
    evade::viz::LogTimeline t(std::move(events));
    if (!png.empty()) return snapshot(t, *w, p, at, png);
    if (!moments_dir.empty()) return snapshot_moments(t, *w, p, moments, moments_dir);
    return run_log(t, *w, p, at, speed, paused);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", kName, e.what());
    return 1;
  }
}
