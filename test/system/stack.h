// Runs the whole evade stack (simulator and every process) as separate
// programs, as run_scenario does, so that system tests can kill and restart
// them. Must run inside a private network namespace (NETNS tests).
#pragma once

#include <signal.h>
#include <sys/types.h>

#include <map>
#include <string>
#include <vector>

namespace evade::testing {

class Stack {
 public:
  // Prepares a run directory and a run configuration for the scenario.
  Stack(const std::string& scenario, const std::string& dir);
  ~Stack();  // stops everything still running

  void start_all(const std::string& planner_mode = "");
  void start(const std::string& name);
  void kill(const std::string& name, int sig = SIGKILL);
  bool alive(const std::string& name);
  std::string output_of(const std::string& name) const;  // its log file's tail
  const std::string& url() const { return url_; }

 private:
  std::vector<std::string> command(const std::string& name) const;
  std::string scenario_, dir_, config_, device_, start_pose_, url_, mode_;
  std::map<std::string, pid_t> pids_;
};

}  // namespace evade::testing
