#include <gtest/gtest.h>

#include "bus/memory_bus.h"
#include "route/route_publisher.h"

namespace evade::route {
namespace {

TEST(Route, PublishesTheConfiguredPathPeriodically) {
  auto root = config::load_string("route:\n  waypoints: [[-10, 0], [0, 1], [9, 0]]\n  publish_period_s: 0.5\n",
                                  "robot.yaml");
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
  auto extra = config::load_string("route:\n  waypoints: [[0, 0], [1, 0]]\n  publish_period_s: 1\n  speed: 2\n",
                                   "r.yaml");
  EXPECT_THROW(RouteParams::from_config(extra.section("route")), config::ConfigError);
}

}  // namespace
}  // namespace evade::route
