// evade-viz --snapshot under Xvfb (xvfb-run): the PNG exists, has the
// configured window size, and shows the robot's footprint, the true
// obstacles, the plan and the route of the golden paper_sim window.
#include <cairo.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <set>
#include <string>

namespace {

struct Png {
  int width = 0, height = 0;
  int robot_green = 0, truth_cyan = 0, plan_green = 0, route = 0;
  size_t colours = 0;
};

Png inspect(const std::string& path) {
  Png out;
  cairo_surface_t* s = cairo_image_surface_create_from_png(path.c_str());
  if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
    cairo_surface_destroy(s);
    return out;
  }
  out.width = cairo_image_surface_get_width(s);
  out.height = cairo_image_surface_get_height(s);
  const int stride = cairo_image_surface_get_stride(s);
  const unsigned char* d = cairo_image_surface_get_data(s);
  std::set<uint32_t> colours;
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      const uint32_t px = *reinterpret_cast<const uint32_t*>(d + y * stride + 4 * x);
      const int r = (px >> 16) & 0xff, g = (px >> 8) & 0xff, b = px & 0xff;
      colours.insert(px & 0xffffff);
      // Lines are drawn unlit, so in their exact colours (scene.cpp), +-2 for rounding.
      auto is = [&](int R, int G, int B) {
        return std::abs(r - R) <= 2 && std::abs(g - G) <= 2 && std::abs(b - B) <= 2;
      };
      if (is(51, 255, 51)) ++out.robot_green;  // (0.2, 1, 0.2)
      if (is(0, 230, 255)) ++out.truth_cyan;   // (0, 0.9, 1)
      if (is(26, 230, 76)) ++out.plan_green;   // status ok (0.1, 0.9, 0.3)
      if (is(208, 208, 209)) ++out.route;      // white at opacity 0.8 over the background
    }
  out.colours = colours.size();
  cairo_surface_destroy(s);
  return out;
}

int run(const std::string& cmd) {
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(VizSnapshot, AFrameOfTheGoldenRunShowsTheRobotAndTheTruth) {
  const std::string png = ::testing::TempDir() + "viz_snapshot_" + std::to_string(::getpid()) + ".png";
  std::remove(png.c_str());
  const std::string src = EVADE_SOURCE_DIR;
  const std::string cmd = "xvfb-run -a -s '-screen 0 1280x800x24' " + std::string(EVADE_VIZ_BIN) + " --config " + src +
                          "/config/robot.yaml --log " + src +
                          "/logs/paper_sim_crossing/input.lcmlog --at 1.5 --snapshot " + png + " 2>/dev/null";
  ASSERT_EQ(run(cmd), 0) << cmd;
  const Png p = inspect(png);
  EXPECT_EQ(p.width, 1280);  // viz.window_width_px
  EXPECT_EQ(p.height, 800);  // viz.window_height_px
  EXPECT_GT(p.colours, 50u) << "a blank frame has one colour";
  EXPECT_GT(p.robot_green, 100) << "the robot's footprint";
  EXPECT_GT(p.truth_cyan, 100) << "the true obstacles";
  EXPECT_GT(p.plan_green, 20) << "the plan (status ok)";
  EXPECT_GT(p.route, 100) << "the route";
}

TEST(VizSnapshot, ABadLogIsAClearError) {
  const std::string bad = ::testing::TempDir() + "viz_not_a_log_" + std::to_string(::getpid());
  std::FILE* f = std::fopen(bad.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fputs("not an lcm log", f);
  std::fclose(f);
  const std::string viz = "DISPLAY=:0 " + std::string(EVADE_VIZ_BIN);  // the log is read before any window opens
  EXPECT_EQ(run(viz + " --log " + bad + " --snapshot /tmp/never.png 2>/dev/null"), 1);
  EXPECT_EQ(run(viz + " --log /no/such.lcmlog --snapshot /tmp/never.png 2>/dev/null"), 1);
  std::remove(bad.c_str());
}

TEST(VizSnapshot, NoDisplayIsAClearError) {
  const std::string src = EVADE_SOURCE_DIR;
  EXPECT_EQ(run("env -u DISPLAY " + std::string(EVADE_VIZ_BIN) + " --log " + src +
                "/logs/paper_sim_crossing/input.lcmlog --snapshot /tmp/never.png 2>/dev/null"),
            2);
}

}  // namespace
