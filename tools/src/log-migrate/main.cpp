// log-migrate: carries a log across a change of lcmtypes that only
// appended fields, so that golden logs need not be recorded again.
//
//   log-migrate odometry-epoch IN.lcmlog OUT.lcmlog [--force]
//
// odometry-epoch (issue 20): ODOMETRY encoded before odometry_t gained
// `int64_t epoch` (fingerprint, utime, x, y, yaw, v, omega: 56 bytes) is
// re-encoded with the current type and epoch 0 (one frame throughout, as
// the recording was). Every other event is copied as it is. OUT may be IN
// only with --force (it is written to a temporary file first).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstring>
#include <filesystem>

#include "bus/core.h"
#include "bus/log.h"
#include "evade/odometry_t.hpp"

namespace {

int64_t be64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | p[i];
  return static_cast<int64_t>(v);
}
double be_double(const uint8_t* p) {
  const int64_t bits = be64(p);
  double d;
  std::memcpy(&d, &bits, sizeof d);
  return d;
}

constexpr size_t kOldOdometrySize = 8 + 8 + 5 * 8;

}  // namespace

int main(int argc, char** argv) {
  namespace bus = evade::bus;
  namespace fs = std::filesystem;
  CLI::App app{"evade log-migrate: carry a log across an appended-field lcmtypes change"};
  std::string migration, in, out;
  bool force = false;
  app.add_option("migration", migration, "odometry-epoch")->required()->check(CLI::IsMember({"odometry-epoch"}));
  app.add_option("in", in, "input log")->required()->check(CLI::ExistingFile);
  app.add_option("out", out, "output log")->required();
  app.add_flag("--force", force, "replace OUT if it exists (also IN itself)");
  CLI11_PARSE(app, argc, argv);
  if (fs::exists(out) && !force) {
    std::fprintf(stderr, "log-migrate: %s exists; refusing to overwrite it without --force\n", out.c_str());
    return 2;
  }
  std::vector<bus::LogEvent> events = bus::read_log(in);
  size_t migrated = 0, current = 0;
  for (auto& e : events) {
    if (e.channel != "ODOMETRY") continue;
    evade::odometry_t m;
    if (bus::decode(e.data.data(), e.data.size(), &m)) {
      ++current;
      continue;
    }
    if (e.data.size() != kOldOdometrySize) {
      std::fprintf(stderr, "log-migrate: an ODOMETRY of %zu bytes is neither the old nor the current type\n",
                   e.data.size());
      return 1;
    }
    const uint8_t* p = e.data.data() + 8;
    m = evade::odometry_t{};
    m.utime = be64(p);
    m.x = be_double(p + 8);
    m.y = be_double(p + 16);
    m.yaw = be_double(p + 24);
    m.v = be_double(p + 32);
    m.omega = be_double(p + 40);
    m.epoch = 0;
    e.data = bus::encode(m);
    ++migrated;
  }
  const std::string tmp = out + ".migrating";
  bus::write_log(tmp, events);
  fs::rename(tmp, out);
  std::printf("log-migrate: %s -> %s: %zu ODOMETRY migrated, %zu already current, %zu events\n", in.c_str(),
              out.c_str(), migrated, current, events.size());
  return 0;
}
