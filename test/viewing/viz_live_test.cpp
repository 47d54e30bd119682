// evade-viz live, inside a private network namespace (NETNS) under
// xvfb-run: ODOMETRY and ROUTE published by the test are drawn (the
// footprint's and the route's colours in the frame it writes after
// listening --at seconds).
#include <cairo.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <thread>

#include "evade/odometry_t.hpp"
#include "evade/path_t.hpp"

namespace {

// Pixels within 2 of an RGB colour.
int count_colour(const std::string& png, int R, int G, int B, int* width) {
  cairo_surface_t* s = cairo_image_surface_create_from_png(png.c_str());
  int n = 0;
  *width = 0;
  if (cairo_surface_status(s) == CAIRO_STATUS_SUCCESS) {
    *width = cairo_image_surface_get_width(s);
    const int h = cairo_image_surface_get_height(s), stride = cairo_image_surface_get_stride(s);
    const unsigned char* d = cairo_image_surface_get_data(s);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < *width; ++x) {
        const uint32_t px = *reinterpret_cast<const uint32_t*>(d + y * stride + 4 * x);
        const int r = (px >> 16) & 0xff, g = (px >> 8) & 0xff, b = px & 0xff;
        n += std::abs(r - R) <= 2 && std::abs(g - G) <= 2 && std::abs(b - B) <= 2;
      }
  }
  cairo_surface_destroy(s);
  return n;
}

TEST(VizLive, DrawsWhatIsOnTheBus) {
  const std::string png = ::testing::TempDir() + "viz_live_" + std::to_string(::getpid()) + ".png";
  std::remove(png.c_str());
  const std::string src = EVADE_SOURCE_DIR;
  const pid_t pid = ::fork();
  if (pid == 0) {
    const std::string cmd = "exec xvfb-run -a -s '-screen 0 1280x800x24' " + std::string(EVADE_VIZ_BIN) + " --config " +
                            src + "/config/robot.yaml --at 2 --snapshot " + png + " 2>/dev/null";
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  lcm::LCM lcm;  // $LCM_DEFAULT_URL: the namespace's group
  ASSERT_TRUE(lcm.good());
  evade::path_t route{};
  route.x = {-5, 5};
  route.y = {0, 0};
  route.n = 2;
  evade::odometry_t odo{};
  int status = 0;
  bool exited = false;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!exited && std::chrono::steady_clock::now() < end) {
    odo.utime =
        std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
            .count();
    route.utime = odo.utime;
    lcm.publish("ODOMETRY", &odo);
    lcm.publish("ROUTE", &route);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    exited = ::waitpid(pid, &status, WNOHANG) == pid;
  }
  if (!exited) {
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &status, 0);
  }
  ASSERT_TRUE(exited) << "evade-viz did not write its frame within 30 s";
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  int width = 0;
  EXPECT_GT(count_colour(png, 51, 255, 51, &width), 100) << "the footprint at the odometry's pose";
  EXPECT_GT(count_colour(png, 208, 208, 209, &width), 100) << "the route";
  EXPECT_EQ(width, 1280);
}

}  // namespace
