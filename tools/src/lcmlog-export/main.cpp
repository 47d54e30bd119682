// lcmlog-export LOG [--channel NAME]...
// Prints an lcm-logger log as JSON lines, one message a line:
//   {"channel":"ODOMETRY","utime":<log timestamp, us>,"type":"odometry_t","msg":{...fields...}}
// Messages of unknown type or that fail to decode print "msg":null with
// their size, and are counted on stderr; the exit status is then 1.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <set>

#include "bus/lcm_schema.h"
#include "bus/log.h"

int main(int argc, char** argv) {
  CLI::App app{"Print an lcm-logger log as JSON lines"};
  std::string path;
  std::vector<std::string> channels;
  app.add_option("log", path, "lcm-logger file")->required();
  app.add_option("--channel", channels, "only these channels (repeatable)");
  CLI11_PARSE(app, argc, argv);

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
