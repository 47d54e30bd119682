// Compares the contract docs/SPEC.md with the repository.
//
// From the SPEC: the channel table (channel -> type, and every `evade.*`
// type it names), the binaries of the process table and the channels named
// in its reads/writes columns, the programs of the tools list.
//
// From the code: the lcm types (package.struct of lcmtypes/*.lcm), the
// binaries of procs/*/CMakeLists.txt, the programs in tools/, and every
// channel the non-test sources (lib/, procs/, tools/src/) use on the bus:
// the first argument of subscribe / publish / publish_raw, `k*Channel`
// string constants, and `channel == "..."` comparisons of log readers. An
// argument that is neither a literal, a known constant nor a parameter
// declaration (a Sink's `publish(const std::string& channel, ...)`) is
// reported (outside lib/bus, which forwards whatever channel it is given),
// so that no channel escapes the check.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

namespace evade::spec {

struct Spec {
  std::map<std::string, std::string> channel_type;  // channel table: channel -> evade.type
  std::set<std::string> types;                      // every evade.* named in the channel table
  std::set<std::string> binaries;                   // process table, first column
  std::set<std::string> process_channels;           // channels in the process table's reads/writes
  std::set<std::string> tools;                      // tools list: first word of each entry
};

// The channel argument of one subscribe / publish / publish_raw call.
struct ChannelUse {
  std::string where;  // file:line
  std::string arg;    // as written: "LITERAL", kConstant or anything else
  std::string type;   // evade.x_t of subscribe<evade::x_t>, else empty
  bool generic_bus;   // in lib/bus: an argument that is not a channel name is fine
};

struct Code {
  std::vector<ChannelUse> uses;
  std::map<std::string, std::string> constants;           // kFooChannel -> "FOO"
  std::map<std::string, std::set<std::string>> channels;  // constants and comparisons: channel -> file:line
  std::set<std::string> types;                            // lcmtypes/: package.struct
  std::set<std::string> binaries;                         // procs/*/CMakeLists.txt add_executable
  std::set<std::string> tools;                            // executable files directly in tools/
};

Spec parse_spec(const std::string& markdown);

// Adds what one source file uses on the bus. `label` names it in messages;
// `generic_bus` is true for lib/bus, whose adapters forward any channel.
void scan_source(const std::string& label, const std::string& text, bool generic_bus, Code* code);
// Adds one lcmtypes/*.lcm file's package.struct.
void scan_lcm_type(const std::string& text, Code* code);
// Everything in the repository at `root`.
Code scan_repository(const std::string& root);

// One line per disagreement; empty when the SPEC and the code agree.
std::vector<std::string> compare(const Spec& spec, const Code& code);

}  // namespace evade::spec
