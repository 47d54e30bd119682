// lcmlog-export LOG [--channel NAME]...
// Prints an lcm-logger log as JSON lines, one message a line:
//   {"channel":"ODOMETRY","utime":<log timestamp, us>,"type":"odometry_t","msg":{...fields...}}
// Messages of unknown type or that fail to decode print "msg":null with
// their size, and are counted on stderr; the exit status is then 1.
//
// lcmlog-export LOG --pcd DIR [--config FILE]
// Writes each revolution's motion-compensated cloud (world frame) and each
// elevation map as binary PCD files (pcd_export.h). The configuration (LiDAR
// decoder and mount for LIDAR_SCAN, sweep slicing) defaults to the robot.yaml
// beside the log (run_scenario and tools/launch write one), else the
// default robot configuration.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <set>

#include "bus/lcm_schema.h"
#include "bus/log.h"
#include "bus/process_main.h"
#include "config/config.h"
#include "config/robot_profile.h"
#include "pcd_export.h"

namespace {

int export_pcd(const std::string& log, const std::string& dir, std::string config, const std::string& robot) {
  if (config.empty()) {
    const auto beside = std::filesystem::path(log).parent_path() / "robot.yaml";
    config = std::filesystem::exists(beside) ? beside.string() : evade::config::default_config_path();
  }
  try {
    const auto options = evade::pcd_export::Options::from_config(evade::config::load_robot_config(config, {robot, ""}));
    const auto st = evade::pcd_export::export_log(log, dir, options);
    std::fprintf(stderr,
                 "lcmlog-export: %s -> %s (config %s): %lld clouds (%s, %lld points), %lld maps; "
                 "%lld revolutions without odometry, %lld invalid points, %lld malformed messages\n",
                 log.c_str(), dir.c_str(), config.c_str(), static_cast<long long>(st.clouds_written),
                 st.from_scans ? "decoded from LIDAR_SCAN" : "from LIDAR_POINTS",
                 static_cast<long long>(st.points_written), static_cast<long long>(st.maps_written),
                 static_cast<long long>(st.clouds_without_pose), static_cast<long long>(st.points_invalid),
                 static_cast<long long>(st.malformed));
    if (st.scans_other_model)
      std::fprintf(stderr, "lcmlog-export: %lld LIDAR_SCAN of another sensor model than lidar.model, skipped\n",
                   static_cast<long long>(st.scans_other_model));
    return st.malformed || st.scans_other_model ? 1 : 0;
  } catch (const evade::config::ConfigError& e) {
    std::fprintf(stderr, "lcmlog-export: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lcmlog-export: %s\n", e.what());
    return 2;
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Print an lcm-logger log as JSON lines"};
  std::string path;
  std::vector<std::string> channels;
  app.add_option("log", path, "lcm-logger file")->required();
  app.add_option("--channel", channels, "only these channels (repeatable)");
  std::string pcd_dir;
  evade::bus::CommonOptions opts;
  app.add_option("--pcd", pcd_dir, "write clouds and elevation maps as PCD files into DIR instead");
  evade::bus::add_robot_options(app, opts,
                                false);  // with --pcd: --config (default: robot.yaml beside the log), --robot
  CLI11_PARSE(app, argc, argv);
  if (!pcd_dir.empty()) {
    if (!channels.empty()) {
      std::fprintf(stderr, "lcmlog-export: --pcd and --channel exclude each other\n");
      return 2;
    }
    return export_pcd(path, pcd_dir, opts.config_path, opts.robot);
  }

  const auto& schema = evade::bus::LcmSchema::evade();
  std::set<std::string> wanted(channels.begin(), channels.end());
  long long undecoded = 0;
  try {
    evade::bus::for_each_event(path, [&](const evade::bus::LogEvent& e) {
      if (!wanted.empty() && !wanted.count(e.channel)) return;
      std::string type;
      auto v = schema.decode(e.data.data(), e.data.size(), &type);
      evade::bus::Value ch;
      ch.kind = evade::bus::Value::Kind::String;
      ch.s = e.channel;
      std::string line = "{\"channel\":" + evade::bus::to_json(ch) + ",\"utime\":" + std::to_string(e.timestamp);
      if (v) {
        line += ",\"type\":\"" + type + "\",\"msg\":" + evade::bus::to_json(*v) + "}";
      } else {
        ++undecoded;
        line += ",\"type\":null,\"size\":" + std::to_string(e.data.size()) + ",\"msg\":null}";
      }
      std::fputs(line.c_str(), stdout);
      std::fputc('\n', stdout);
    });
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "lcmlog-export: %s\n", ex.what());
    return 2;
  }
  if (undecoded) {
    std::fprintf(stderr, "lcmlog-export: %lld messages of unknown type or malformed\n", undecoded);
    return 1;
  }
  return 0;
}
