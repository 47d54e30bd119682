#include "stack.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "bus/live_bus.h"

namespace evade::testing {
namespace {

std::string bin(const std::string& name) { return std::string(EVADE_BIN_DIR) + "/" + name; }

std::string capture(const std::string& cmd) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) throw std::runtime_error("cannot run " + cmd);
  char buf[512];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  if (pclose(p) != 0) throw std::runtime_error("failed: " + cmd);
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

}  // namespace

Stack::Stack(const std::string& scenario, const std::string& dir)
    : scenario_(scenario), dir_(dir), url_(bus::default_lcm_url()) {
  std::system(("mkdir -p '" + dir_ + "'").c_str());
  config_ = dir_ + "/robot.yaml";
  device_ = dir_ + "/scout.pty";
  capture(bin("scenario-info") + " '" + scenario_ + "' --write-config '" + config_ + "' --config '" +
          std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml'");
  start_pose_ = capture(bin("scenario-info") + " '" + scenario_ + "' --start-pose");
}

Stack::~Stack() {
  for (auto& [name, pid] : pids_) ::kill(pid, SIGTERM);
  for (auto& [name, pid] : pids_) {
    for (int i = 0; i < 20; ++i) {
      if (waitpid(pid, nullptr, WNOHANG) != 0) break;
      usleep(100'000);
    }
    ::kill(pid, SIGKILL);
    waitpid(pid, nullptr, 0);
  }
}

std::vector<std::string> Stack::command(const std::string& name) const {
  std::vector<std::string> c{bin(name)};
  if (name == "sim") c.insert(c.end(), {"--scenario", scenario_, "--device", device_});
  if (name == "base_driver") c.insert(c.end(), {"--device", device_, "--initial-pose", start_pose_});
  if (name == "route") c.insert(c.end(), {"--scenario", scenario_});
  if (name == "planner" && !mode_.empty()) c.insert(c.end(), {"--mode", mode_});
  c.insert(c.end(), {"--config", config_, "--lcm-url", url_});
  return c;
}

void Stack::start(const std::string& name) {
  auto args = command(name);
  std::string log = dir_ + "/" + name + ".log";
  pid_t pid = fork();
  if (pid == 0) {
    int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
    }
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  pids_[name] = pid;
}

void Stack::start_all(const std::string& planner_mode) {
  mode_ = planner_mode;
  for (const char* n :
       {"sim", "base_driver", "lidar_driver", "elevation_map", "tracker", "predictor", "planner", "route"})
    start(n);
}

void Stack::kill(const std::string& name, int sig) {
  auto it = pids_.find(name);
  if (it == pids_.end()) return;
  ::kill(it->second, sig);
  waitpid(it->second, nullptr, 0);
  pids_.erase(it);
}

bool Stack::alive(const std::string& name) {
  auto it = pids_.find(name);
  return it != pids_.end() && waitpid(it->second, nullptr, WNOHANG) == 0;
}

std::string Stack::output_of(const std::string& name) const {
  std::ifstream f(dir_ + "/" + name + ".log");
  std::stringstream ss;
  ss << f.rdbuf();
  std::string s = ss.str();
  return s.size() > 2000 ? s.substr(s.size() - 2000) : s;
}

}  // namespace evade::testing
