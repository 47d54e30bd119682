// bus_echo: EchoCore as a process, through the same process_main as every
// evade process (so it has --config, --lcm-url, --replay).
#include "bus/process_main.h"
#include "echo_core.h"

int main(int argc, char** argv) {
  return evade::bus::process_main(argc, argv, "bus_echo", nullptr, [](const evade::config::Node&) {
    return std::make_unique<evade::bus::testing::EchoCore>("ECHO_IN", "ECHO_OUT");
  });
}
