#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "bus/memory_bus.h"
#include "route/route_publisher.h"

namespace evade::route {
namespace {

TEST(Route, PublishesTheConfiguredPathPeriodically) {
  auto root =
      config::load_string("route:\n  waypoints: [[-10, 0], [0, 1], [9, 0]]\n  publish_period_s: 0.5\n", "robot.yaml");
  RoutePublisher core(RouteParams::from_config(root.section("route")));
  bus::MemoryBus bus;
  bus.add(core);
  bus.advance_to(1'000'000);
  bus.advance_to(2'000'000);
  auto routes = bus.decoded<evade::path_t>("ROUTE");
  ASSERT_EQ(routes.size(), 3u);  // 1.0, 1.5, 2.0 s
  EXPECT_EQ(routes[2].utime, 2'000'000);
  ASSERT_EQ(routes[0].n, 3);
  EXPECT_EQ(routes[0].x, (std::vector<double>{-10, 0, 9}));
  EXPECT_EQ(routes[0].y, (std::vector<double>{0, 1, 0}));
}

TEST(Route, RejectsBadRoutes) {
  auto one = config::load_string("route:\n  waypoints: [[0, 0]]\n  publish_period_s: 1\n", "r.yaml");
  EXPECT_THROW(RouteParams::from_config(one.section("route")), config::ConfigError);
  auto dup = config::load_string("route:\n  waypoints: [[0, 0], [0, 0]]\n  publish_period_s: 1\n", "r.yaml");
  try {
    RouteParams::from_config(dup.section("route"));
    FAIL() << "coinciding points accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_STREQ(e.what(), "r.yaml:2: key 'route.waypoints': points 0 and 1 coincide");
  }
  auto extra =
      config::load_string("route:\n  waypoints: [[0, 0], [1, 0]]\n  publish_period_s: 1\n  speed: 2\n", "r.yaml");
  EXPECT_THROW(RouteParams::from_config(extra.section("route")), config::ConfigError);
}

TEST(Route, ARouteFromGotoReplacesTheConfiguredOneAndIsRepeated) {
  auto root = config::load_string("route:\n  waypoints: [[-10, 0], [9, 0]]\n  publish_period_s: 1.0\n", "robot.yaml");
  RoutePublisher core(RouteParams::from_config(root.section("route")));
  bus::MemoryBus bus;
  bus.add(core);
  bus.advance_to(1'000'000);  // the configured route
  bus.inject("ROUTE", make_path(route_to(-3.0, 0.5, 4.0, 2.0), 1'200'000), 1'200'000);
  bus.advance_to(2'000'000);
  bus.advance_to(3'000'000);
  auto routes = bus.decoded<evade::path_t>("ROUTE");
  ASSERT_EQ(routes.size(), 3u);  // 1, 2, 3 s (the injected one is not the core's)
  EXPECT_EQ(routes[0].x, (std::vector<double>{-10, 9}));
  EXPECT_EQ(routes[1].x, (std::vector<double>{-3.0, 4.0}));
  EXPECT_EQ(routes[2].y, (std::vector<double>{0.5, 2.0}));
  EXPECT_EQ(routes[2].utime, 3'000'000);
  EXPECT_EQ(core.counter("route_replaced"), 1);
}

TEST(Route, AnInvalidRouteOnTheBusIsCountedAndIgnored) {
  auto root = config::load_string("route:\n  waypoints: [[-10, 0], [9, 0]]\n  publish_period_s: 1.0\n", "robot.yaml");
  RoutePublisher core(RouteParams::from_config(root.section("route")));
  bus::MemoryBus bus;
  bus.add(core);
  bus.advance_to(1'000'000);
  evade::path_t one = make_path({{1.0, 1.0}}, 1'100'000);
  evade::path_t nan = make_path({{0.0, 0.0}, {std::nan(""), 1.0}}, 1'200'000);
  evade::path_t bad_n = make_path({{0.0, 0.0}, {1.0, 1.0}}, 1'300'000);
  bad_n.n = 5;  // encodes fine only if the arrays match: keep n, shrink nothing
  bus.inject("ROUTE", one, 1'100'000);
  bus.inject("ROUTE", nan, 1'200'000);
  bus.advance_to(2'000'000);
  EXPECT_EQ(core.counter("route_rejected"), 2);
  EXPECT_EQ(core.counter("route_replaced"), 0);
  EXPECT_EQ(core.path().x, (std::vector<double>{-10, 9}));
  EXPECT_EQ(validate_route(bad_n), "n does not match x and y");
}

TEST(Route, GotoNeedsAGoalAwayFromTheRobot) {
  EXPECT_EQ(route_to(1.0, 2.0, 3.0, 4.0), (std::vector<std::vector<double>>{{1.0, 2.0}, {3.0, 4.0}}));
  EXPECT_THROW(route_to(1.0, 2.0, 1.0, 2.0), std::invalid_argument);
  EXPECT_THROW(route_to(1.0, 2.0, std::nan(""), 2.0), std::invalid_argument);
}

TEST(Route, RouteFilesAreReadStrictly) {
  const std::string path = ::testing::TempDir() + "route_file_test.yaml";
  std::ofstream(path) << "route: [[0, 0], [5, 0], [5, 5]]\n";
  EXPECT_EQ(load_route_file(path), (std::vector<std::vector<double>>{{0, 0}, {5, 0}, {5, 5}}));
  std::ofstream(path) << "route: [[0, 0], [5, 0]]\nspeed: 2\n";
  try {
    load_route_file(path);
    FAIL() << "unknown key accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(":2: key 'speed': unknown key"), std::string::npos) << e.what();
  }
  std::ofstream(path) << "route: [[0, 0]]\n";
  EXPECT_THROW(load_route_file(path), config::ConfigError);
  std::remove(path.c_str());
}

TEST(Route, FactoryTakesAScenariosWaypointsAndNamesItsFileWhenBad) {
  auto root = config::load_string("route:\n  waypoints: [[-10, 0], [9, 0]]\n  publish_period_s: 0.5\n", "robot.yaml");
  auto own = RoutePublisher::from_config(root);
  EXPECT_EQ(own->path().x, (std::vector<double>{-10, 9}));
  using Waypoints = std::vector<std::vector<double>>;
  auto scenario = RoutePublisher::from_config(root, Waypoints{{0, 0}, {3, 4}, {5, 4}}, "s.yaml");
  ASSERT_EQ(scenario->path().n, 3);
  EXPECT_EQ(scenario->path().x, (std::vector<double>{0, 3, 5}));
  EXPECT_EQ(scenario->path().y, (std::vector<double>{0, 4, 4}));
  try {
    RoutePublisher::from_config(root, Waypoints{{1, 1}}, "s.yaml");
    FAIL() << "a one-point route accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("s.yaml:0: key 'route': ", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace evade::route
