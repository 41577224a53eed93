// The options a --help text of the CLI prints and defines, and every command's --help as the built
// CLI prints it: for the docs, completion and manual page tests.
#pragma once

#include <cctype>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli.h"

namespace dacrt::test {

using Names = std::set<std::string>;

inline bool word_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
}

inline std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// Every long option written in `text`: "--" not inside a word, then a lower-case name.
inline Names long_options(const std::string& text) {
  Names names;
  for (size_t i = 0; i + 2 < text.size(); ++i) {
    if (text.compare(i, 2, "--") != 0 || (i > 0 && word_char(text[i - 1])) ||
        !std::islower(static_cast<unsigned char>(text[i + 2])))
      continue;
    size_t end = i + 2;
    while (end < text.size() &&
           (std::islower(static_cast<unsigned char>(text[end])) ||
            std::isdigit(static_cast<unsigned char>(text[end])) || text[end] == '-'))
      ++end;
    names.insert(text.substr(i, end - i));
    i = end - 1;
  }
  return names;
}

// The short options a help text lists: "-x" at the start of an option line ("  -o, --output").
inline Names short_options(const std::string& help) {
  Names names;
  for (const std::string& line : lines_of(help)) {
    const size_t at = line.find_first_not_of(' ');
    if (at == 0 || at == std::string::npos || at + 2 >= line.size()) continue;
    if (line[at] == '-' && std::isalpha(static_cast<unsigned char>(line[at + 1])) &&
        (line[at + 2] == ',' || line[at + 2] == ' '))
      names.insert(line.substr(at, 2));
  }
  return names;
}

// Every option a help text prints, in its option lines and in its prose.
inline Names printed_options(const std::string& help) {
  Names names = long_options(help);
  const Names shorts = short_options(help);
  names.insert(shorts.begin(), shorts.end());
  return names;
}

// The options a command's help defines: the option column of its option lines ("  --width W,
// --height H      resolution …": the text before the description) and those of its "Usage:"
// line ("Usage: dacrt info SCENE [--scene INDEX]"); not those its prose mentions.
inline Names defined_options(const std::string& help) {
  Names names = short_options(help);
  for (const std::string& line : lines_of(help)) {
    std::string column;
    const size_t at = line.find_first_not_of(' ');
    if (line.rfind("Usage:", 0) == 0)
      column = line;
    else if (at != 0 && at != std::string::npos && line[at] == '-')
      column = line.substr(at, line.find("  ", at) - at);
    const Names longs = long_options(column);
    names.insert(longs.begin(), longs.end());
  }
  return names;
}

// `name` in `text` as a whole token (so --backend is not found inside --backend-option).
inline bool has_token(const std::string& text, const std::string& name) {
  for (size_t at = text.find(name); at != std::string::npos; at = text.find(name, at + 1)) {
    const size_t end = at + name.size();
    if ((at == 0 || !word_char(text[at - 1])) && (end == text.size() || !word_char(text[end])))
      return true;
  }
  return false;
}

// The commands `dacrt --help` lists ("  dacrt render SCENE [options]  ...": render).
inline std::vector<std::string> listed_commands(const std::string& main_help) {
  std::vector<std::string> commands;
  const std::string prefix = "  dacrt ";
  for (const std::string& line : lines_of(main_help))
    if (line.rfind(prefix, 0) == 0 && line.size() > prefix.size() && line[prefix.size()] != '-')
      commands.push_back(line.substr(prefix.size(), line.find(' ', prefix.size()) - prefix.size()));
  return commands;
}

struct Help {
  std::string command, text;
};

// The --help of the top level (command "") and of every command it lists, as the built CLI
// prints them.
inline std::vector<Help> helps() {
  TempDir dir("help-texts");
  const Run top = run(dir, "--help");
  REQUIRE(top.code == 0);
  std::vector<Help> out = {{"", top.out}};
  for (const std::string& command : listed_commands(top.out)) {
    const Run r = run(dir, command + " --help");
    INFO("dacrt " << command << " --help");
    REQUIRE(r.code == 0);
    out.push_back({command, r.out});
  }
  REQUIRE(out.size() >= 8);
  return out;
}

// The help of `command` among `all`.
inline std::string help_of(const std::vector<Help>& all, const std::string& command) {
  for (const Help& h : all)
    if (h.command == command) return h.text;
  FAIL("dacrt --help does not list " << command);
  return "";
}

}  // namespace dacrt::test
