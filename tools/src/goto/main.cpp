// goto: sends the robot a new route at run time, on ROUTE.
//
//   goto X Y [--lcm-url U] [--config F] [--odometry-wait-s S]   straight from where the robot
//                                                  is (its next ODOMETRY) to (X, Y)
//   goto --route FILE [--lcm-url U]                the polyline of FILE
//                                                  (`route: [[x, y], ...]`)
// Metres, in the odometry/world frame. The route process adopts the new
// route and repeats it (lib/route); the planner drives to its end
// (PLAN.status GOAL there). Exit 0 sent, 1 no ODOMETRY heard, 2 bad input.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "bus/auth.h"
#include "bus/core.h"
#include "bus/live_bus.h"
#include "bus/process_main.h"
#include "config/config.h"
#include "config/robot_profile.h"
#include "evade/odometry_t.hpp"
#include "route/route_publisher.h"

namespace {

// The robot's position from the first ODOMETRY within `wait_s`.
std::optional<evade::odometry_t> wait_for_odometry(lcm::LCM& lcm, double wait_s) {
  std::optional<evade::odometry_t> got;
  struct Handler {
    std::optional<evade::odometry_t>* out;
    void on(const lcm::ReceiveBuffer* rbuf, const std::string&) {
      evade::odometry_t m;
      if (evade::bus::decode(static_cast<const uint8_t*>(rbuf->data), rbuf->data_size, &m)) *out = m;
    }
  } handler{&got};
  lcm::Subscription* sub = lcm.subscribe("ODOMETRY", &Handler::on, &handler);
  const int64_t until = evade::bus::wall_utime() + static_cast<int64_t>(wait_s * 1e6);
  for (int64_t now = evade::bus::wall_utime(); !got && now < until; now = evade::bus::wall_utime())
    lcm.handleTimeout(static_cast<int>(std::max<int64_t>(1, (until - now) / 1000)));
  lcm.unsubscribe(sub);
  return got;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"evade goto: a new route at run time, on ROUTE"};
  std::vector<double> goal;
  std::string route_file, url;
  evade::bus::CommonOptions opts;
  double wait_s = 2.0;
  app.add_option("goal", goal, "X Y: the goal (m, odometry/world frame)")->expected(2);
  app.add_option("--route", route_file, "a route file (route: [[x, y], ...]) instead of X Y");
  app.add_option("--lcm-url", url, "LCM URL (default $LCM_DEFAULT_URL, else host-local udpm)");
  evade::bus::add_robot_options(app, opts, false);  // --config (naming the bus key), --robot
  app.add_option("--odometry-wait-s", wait_s, "with X Y: how long to wait for the robot's ODOMETRY")
      ->check(CLI::Range(0.1, 60.0));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // --help: 0; bad arguments: 2
  }
  if (goal.empty() == route_file.empty()) {
    std::fprintf(stderr, "goto: give either X Y or --route FILE\n");
    return 2;
  }
  // ROUTE is authenticated (lib/bus/auth.h): unsigned, route and the planner ignore it.
  std::unique_ptr<evade::bus::HmacAuth> signer;
  try {
    const std::string path = opts.config_path.empty() ? evade::config::default_config_path() : opts.config_path;
    signer = evade::bus::load_auth(evade::config::load_robot_config(path, {opts.robot, ""})).make("goto");
  } catch (const std::exception& e) {  // ConfigError, KeyError
    std::fprintf(stderr, "goto: %s\n", e.what());
    return 2;
  }
  lcm::LCM lcm(url.empty() ? evade::bus::default_lcm_url() : url);
  if (!lcm.good()) {
    std::fprintf(stderr, "goto: cannot open LCM\n");
    return 2;
  }
  std::vector<std::vector<double>> points;
  try {
    if (!route_file.empty()) {
      points = evade::route::load_route_file(route_file);
    } else {
      std::optional<evade::odometry_t> odom = wait_for_odometry(lcm, wait_s);
      if (!odom) {
        std::fprintf(stderr, "goto: no ODOMETRY within %.1f s: where the robot is is unknown\n", wait_s);
        return 1;
      }
      points = evade::route::route_to(odom->x, odom->y, goal[0], goal[1]);
    }
  } catch (const std::exception& e) {  // ConfigError, invalid_argument
    std::fprintf(stderr, "goto: %s\n", e.what());
    return 2;
  }
  const evade::path_t path = evade::route::make_path(points, evade::bus::wall_utime());
  std::vector<uint8_t> data = evade::bus::encode(path);
  signer->sign("ROUTE", path.utime, &data);
  if (lcm.publish("ROUTE", data.data(), static_cast<unsigned>(data.size())) != 0) {
    std::fprintf(stderr, "goto: publishing ROUTE failed\n");
    return 2;
  }
  std::printf("goto: ROUTE of %d points sent, from (%.2f, %.2f) to (%.2f, %.2f)\n", path.n, path.x.front(),
              path.y.front(), path.x.back(), path.y.back());
  return 0;
}
