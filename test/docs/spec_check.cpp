#include "spec_check.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

namespace evade::spec {
namespace {

namespace fs = std::filesystem;

std::string trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

// The cells of a markdown table row; `\|` does not split.
std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::string cur;
  for (size_t i = 1; i < row.size(); ++i) {
    if (row[i] == '|' && row[i - 1] != '\\') {
      out.push_back(trim(cur));
      cur.clear();
    } else {
      cur += row[i];
    }
  }
  return out;
}

// Every `...` span of a text.
std::vector<std::string> code_spans(const std::string& s) {
  std::vector<std::string> out;
  static const std::regex re("`([^`]*)`");
  for (auto it = std::sregex_iterator(s.begin(), s.end(), re); it != std::sregex_iterator(); ++it)
    out.push_back((*it)[1]);
  return out;
}

bool is_channel_name(const std::string& s) { return std::regex_match(s, std::regex("[A-Z][A-Z0-9_]*")); }

void parse_channel_row(const std::vector<std::string>& c, const std::string& row, Spec* spec) {
  const auto name = code_spans(c[0]), type = code_spans(c.size() > 1 ? c[1] : "");
  if (name.size() != 1) return;  // the header row
  spec->channel_type[name[0]] = type.empty() ? "" : type[0];
  static const std::regex re("evade\\.\\w+");
  for (auto it = std::sregex_iterator(row.begin(), row.end(), re); it != std::sregex_iterator(); ++it)
    spec->types.insert(it->str());
}

void parse_process_row(const std::vector<std::string>& c, Spec* spec) {
  const auto name = code_spans(c[0]);
  if (name.size() != 1) return;  // the header row
  spec->binaries.insert(name[0]);
  for (size_t i = 2; i < c.size(); ++i)
    for (const auto& s : code_spans(c[i]))
      if (is_channel_name(s)) spec->process_channels.insert(s);
}

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The text with // and /* */ comments blanked (newlines kept, so line
// numbers hold); string and character literals are left alone.
std::string strip_comments(const std::string& t) {
  std::string out = t;
  enum { kCode, kString, kChar, kLine, kBlock } st = kCode;
  for (size_t i = 0; i < t.size(); ++i) {
    const char c = t[i], n = i + 1 < t.size() ? t[i + 1] : '\0';
    switch (st) {
      case kCode:
        if (c == '"')
          st = kString;
        else if (c == '\'')
          st = kChar;
        else if (c == '/' && n == '/')
          st = kLine;
        else if (c == '/' && n == '*')
          st = kBlock;
        break;
      case kString:
      case kChar:
        if (c == '\\')
          ++i;
        else if (c == (st == kString ? '"' : '\''))
          st = kCode;
        break;
      case kLine:
        if (c == '\n') st = kCode;
        break;
      case kBlock:
        if (c == '*' && n == '/') {
          out[i] = out[i + 1] = ' ';
          ++i;
          st = kCode;
          continue;
        }
        break;
    }
    if ((st == kLine || st == kBlock) && c != '\n') out[i] = ' ';
  }
  return out;
}

int line_of(const std::string& text, size_t pos) {
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(pos), '\n'));
}

struct Resolved {
  std::map<std::string, std::set<std::string>> where;              // channel -> file:line
  std::map<std::string, std::map<std::string, std::string>> type;  // channel -> subscribed type -> file:line
};

// Every use with its channel name: literals as written, constants looked
// up (a constant is defined in one file and used in others).
Resolved resolve(const Code& code, std::vector<std::string>* unresolved) {
  Resolved r;
  r.where = code.channels;
  static const std::regex literal("\"([^\"]*)\"");
  // A parameter declaration (`publish(const std::string& channel, ...)` in a
  // Sink's signature) is not a call: type words, then the parameter's name.
  static const std::regex declaration("(const\\s+)?[\\w:]+(\\s*[&*]+\\s*|\\s+)\\w+");
  for (const auto& u : code.uses) {
    std::smatch m;
    std::string ch;
    if (std::regex_match(u.arg, m, literal)) {
      ch = m[1];
    } else if (code.constants.count(u.arg)) {
      ch = code.constants.at(u.arg);
    } else if (std::regex_match(u.arg, declaration)) {
      continue;
    } else {
      if (!u.generic_bus)
        unresolved->push_back(u.where + ": `" + u.arg + "` is neither a channel literal nor a k*Channel constant");
      continue;
    }
    r.where[ch].insert(u.where);
    if (!u.type.empty()) r.type[ch].emplace(u.type, u.where);
  }
  return r;
}

void scan_calls(const std::string& label, const std::string& text, bool generic_bus, Code* code) {
  static const std::regex call("\\b(subscribe|publish_raw|publish)\\s*(?:<\\s*([\\w:]+)\\s*>)?\\s*\\(\\s*([^,();{}]*)");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), call); it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    const std::string where = label + ":" + std::to_string(line_of(text, static_cast<size_t>(m.position(0))));
    const std::string arg = trim(m[3]);
    std::string type = m[2];
    type = std::regex_replace(type, std::regex("::"), ".");
    code->uses.push_back({where, arg, type, generic_bus});
  }
}

}  // namespace

Spec parse_spec(const std::string& markdown) {
  Spec spec;
  std::istringstream in(markdown);
  std::string line, section;
  while (std::getline(in, line)) {
    if (line.rfind("## ", 0) == 0) section = trim(line.substr(3));
    if (line.rfind("|", 0) == 0) {
      const auto c = cells(line);
      if (c.empty()) continue;
      if (section.rfind("Channels and types", 0) == 0) parse_channel_row(c, line, &spec);
      if (section.rfind("Processes", 0) == 0) parse_process_row(c, &spec);
    } else if (section.rfind("Tools", 0) == 0) {
      // "- `name ARGS...`", the span possibly running on to the next line
      std::smatch m;
      if (std::regex_search(line, m, std::regex("^- `([\\w.-]+)"))) spec.tools.insert(m[1]);
    }
  }
  return spec;
}

void scan_source(const std::string& label, const std::string& raw, bool generic_bus, Code* code) {
  const std::string text = strip_comments(raw);
  scan_calls(label, text, generic_bus, code);
  static const std::regex constant("\\b(k\\w*Channel)\\s*=\\s*\"(\\w*)\"");
  static const std::regex compared("\\bchannel\\s*[!=]=\\s*\"(\\w*)\"|\"(\\w*)\"\\s*[!=]=\\s*[\\w.>-]*channel\\b");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), constant); it != std::sregex_iterator(); ++it) {
    code->constants[(*it)[1]] = (*it)[2];
    code->channels[(*it)[2]].insert(label + ":" + std::to_string(line_of(text, static_cast<size_t>(it->position(0)))));
  }
  for (auto it = std::sregex_iterator(text.begin(), text.end(), compared); it != std::sregex_iterator(); ++it) {
    const std::string ch = (*it)[1].matched ? (*it)[1] : (*it)[2];
    code->channels[ch].insert(label + ":" + std::to_string(line_of(text, static_cast<size_t>(it->position(0)))));
  }
}

void scan_lcm_type(const std::string& raw, Code* code) {
  const std::string text = strip_comments(raw);
  std::smatch pkg;
  const bool has_pkg = std::regex_search(text, pkg, std::regex("\\bpackage\\s+(\\w+)\\s*;"));
  static const std::regex st("\\bstruct\\s+(\\w+)");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), st); it != std::sregex_iterator(); ++it)
    code->types.insert((has_pkg ? pkg[1].str() + "." : std::string()) + (*it)[1].str());
}

Code scan_repository(const std::string& root) {
  Code code;
  const fs::path r(root);
  for (const char* dir : {"lib", "procs", "tools/src"}) {
    for (const auto& e : fs::recursive_directory_iterator(r / dir)) {
      const std::string ext = e.path().extension();
      if (!e.is_regular_file() || (ext != ".h" && ext != ".hpp" && ext != ".cpp" && ext != ".cc")) continue;
      const std::string rel = fs::relative(e.path(), r).generic_string();
      scan_source(rel, read(e.path()), rel.rfind("lib/bus/", 0) == 0, &code);
    }
  }
  for (const auto& e : fs::directory_iterator(r / "lcmtypes"))
    if (e.path().extension() == ".lcm") scan_lcm_type(read(e.path()), &code);
  static const std::regex exe("add_executable\\s*\\(\\s*(\\w+)");
  for (const auto& e : fs::directory_iterator(r / "procs")) {
    const std::string cm = read(e.path() / "CMakeLists.txt");
    for (auto it = std::sregex_iterator(cm.begin(), cm.end(), exe); it != std::sregex_iterator(); ++it)
      code.binaries.insert((*it)[1]);
  }
  for (const auto& e : fs::directory_iterator(r / "tools"))
    if (e.is_regular_file() && (fs::status(e.path()).permissions() & fs::perms::owner_exec) != fs::perms::none)
      code.tools.insert(e.path().filename());
  return code;
}

namespace {

std::string first(const std::set<std::string>& s) { return s.empty() ? "?" : *s.begin(); }

void compare_channels(const Spec& spec, const Code& code, std::vector<std::string>* out) {
  const Resolved used = resolve(code, out);
  for (const auto& [ch, where] : used.where)
    if (!spec.channel_type.count(ch))
      out->push_back("channel " + ch + " (used at " + first(where) + ") is not in the SPEC's channel table");
  for (const auto& [ch, type] : spec.channel_type) {
    if (!used.where.count(ch))
      out->push_back("channel " + ch + " is in the SPEC but no source in lib/, procs/, tools/src/ uses it");
    if (!used.type.count(ch)) continue;
    for (const auto& [sub, where] : used.type.at(ch))
      if (sub != type)
        out->push_back("channel " + ch + ": the SPEC says " + type + ", the code subscribes with " + sub + " at " +
                       where);
  }
  for (const auto& ch : spec.process_channels)
    if (!spec.channel_type.count(ch))
      out->push_back("the process table names " + ch + ", which the channel table does not");
}

void compare_sets(const std::set<std::string>& spec, const std::set<std::string>& code, const std::string& what,
                  const std::string& where, std::vector<std::string>* out) {
  for (const auto& s : spec)
    if (!code.count(s)) out->push_back(what + " " + s + " is in the SPEC but not in " + where);
  for (const auto& s : code)
    if (!spec.count(s)) out->push_back(what + " " + s + " (" + where + ") is not in the SPEC");
}

}  // namespace

std::vector<std::string> compare(const Spec& spec, const Code& code) {
  std::vector<std::string> out;
  if (spec.channel_type.empty()) out.push_back("no channel table found in the SPEC");
  if (spec.binaries.empty()) out.push_back("no process table found in the SPEC");
  compare_channels(spec, code, &out);
  compare_sets(spec.types, code.types, "type", "lcmtypes/", &out);
  compare_sets(spec.binaries, code.binaries, "process", "procs/*/CMakeLists.txt", &out);
  for (const auto& t : spec.tools)
    if (!code.tools.count(t)) out.push_back("tool " + t + " is in the SPEC but tools/" + t + " is not an executable");
  return out;
}

}  // namespace evade::spec
