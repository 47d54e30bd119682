// The default configuration path rule (config.h: config_file_candidates).
// EVADE_BINARY_DIR, EVADE_SOURCE_DIR and EVADE_INSTALL_BIN_TO_SYSCONF (the
// path from the installed executables' folder to <sysconfdir>/evade,
// relative) come from the build (lib/config/CMakeLists.txt).
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "config/config.h"

namespace evade::config {
namespace fs = std::filesystem;
namespace {

// The folder of the running executable; empty if /proc does not say.
fs::path exe_dir() {
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path();
}

bool same_dir(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  return !a.empty() && fs::equivalent(a, b, ec);
}

}  // namespace

std::vector<std::string> config_file_candidates(const std::string& name) {
  std::vector<std::string> out{"config/" + name};
  const fs::path dir = exe_dir();
  if (same_dir(dir, fs::path(EVADE_BINARY_DIR) / "bin")) {
    out.push_back(std::string(EVADE_SOURCE_DIR) + "/config/" + name);
  } else if (!dir.empty()) {
    out.push_back((dir / EVADE_INSTALL_BIN_TO_SYSCONF / name).lexically_normal().string());
  }
  return out;
}

std::string find_config_file(const std::string& name) {
  const std::vector<std::string> candidates = config_file_candidates(name);
  std::error_code ec;
  for (const auto& c : candidates)
    if (fs::is_regular_file(c, ec)) return c;
  return candidates.back();
}

std::string default_config_path() {
  if (const char* env = std::getenv("EVADE_CONFIG"); env && *env) return env;
  return find_config_file("robot.yaml");
}

}  // namespace evade::config
