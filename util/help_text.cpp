// Reading a command's --help text (see help_text.h).
#include "dacrt/util/help_text.h"

#include <algorithm>
#include <cctype>
#include <sstream>

namespace dacrt {

std::vector<std::string> text_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<std::string> text_words(const std::string& text) {
  std::vector<std::string> words;
  std::istringstream in(text);
  for (std::string word; in >> word;) words.push_back(word);
  return words;
}

bool is_option_word(const std::string& word) {
  return word.size() >= 2 && word[0] == '-' &&
         (std::isalpha(static_cast<unsigned char>(word[1])) ||
          (word[1] == '-' && word.size() > 2 && std::islower(static_cast<unsigned char>(word[2]))));
}

// The text of a line from `at` up to its description (two spaces), or to its end.
std::string item_column(const std::string& line, size_t at) {
  const size_t gap = line.find("  ", at);
  return line.substr(at, gap == std::string::npos ? std::string::npos : gap - at);
}

void add_help_option(std::vector<HelpOption>& options, const std::string& name,
                const std::string& short_name, const std::string& value) {
  auto o = std::find_if(options.begin(), options.end(), [&](const HelpOption& h) {
    return h.name == name || (!short_name.empty() && h.short_name == short_name) ||
           (name.size() == 2 && h.short_name == name);
  });
  if (o == options.end()) o = options.insert(options.end(), {name, short_name, {}});
  if (o->short_name.empty()) o->short_name = short_name;
  if (!value.empty() && std::find(o->values.begin(), o->values.end(), value) == o->values.end())
    o->values.push_back(value);
}

namespace {

// An option line of a help: indented by at most 4, an option first.
bool option_line(const std::string& line, size_t& at) {
  at = line.find_first_not_of(' ');
  return at != std::string::npos && at > 0 && at <= 4 &&
         is_option_word(line.substr(at, line.find(' ', at) - at));
}

// The value shown after an option among `words` (from words[k]), quotes kept together, brackets
// dropped ("[NAME.]KEY=VALUE" stays: its bracket is inside).
std::string value_at(const std::vector<std::string>& words, size_t k) {
  if (k >= words.size() || words[k].empty() || words[k][0] == '-' || words[k] == "|") return "";
  std::string v = words[k];
  if (v[0] == '"')
    while (std::count(v.begin(), v.end(), '"') < 2 && ++k < words.size()) v += " " + words[k];
  while (!v.empty() && v.back() == ']') v.pop_back();
  if (v.rfind('[', 0) == 0 && v.find(']') == std::string::npos) v.erase(0, 1);
  return v;
}

}  // namespace

std::vector<HelpOption> help_options(const std::string& help) {
  std::vector<HelpOption> options;
  std::string usage;
  for (const std::string& line : text_lines(help)) {
    if (line.rfind("Usage:", 0) == 0) usage = line;
    size_t at = 0;
    if (!option_line(line, at)) continue;
    // "-o, --output OUT.exr", "--width W, --height H": options separated by ", ".
    std::string short_name, column = item_column(line, at) + ", ";
    for (size_t start = 0, comma; (comma = column.find(", ", start)) != std::string::npos;
         start = comma + 2) {
      const std::vector<std::string> words = text_words(column.substr(start, comma - start));
      if (words.empty() || !is_option_word(words[0])) break;
      if (words[0][1] != '-' && words.size() == 1) {
        short_name = words[0];
        continue;
      }
      add_help_option(options, words[0], words[0][1] == '-' ? short_name : "", value_at(words, 1));
      short_name.clear();
    }
  }
  // The Usage line's options ("[--scene INDEX]"), unless an option line has them already.
  const std::vector<std::string> words = text_words(usage);
  for (size_t k = 0; k < words.size(); ++k) {
    std::string w = words[k];
    while (!w.empty() && w[0] == '[') w.erase(0, 1);
    while (!w.empty() && w.back() == ']') w.pop_back();
    if (!is_option_word(w)) continue;
    const bool known = std::any_of(options.begin(), options.end(), [&](const HelpOption& o) {
      return o.name == w || o.short_name == w;
    });
    const std::string value = words[k].back() == ']' ? "" : value_at(words, k + 1);
    if (!known) add_help_option(options, w, "", value);
  }
  return options;
}

std::vector<std::string> help_option_names(const std::string& help) {
  std::vector<std::string> names;
  for (const HelpOption& o : help_options(help))
    if (o.name.rfind("--", 0) == 0) names.push_back(o.name);
  return names;
}

std::vector<std::string> help_flag_names(const std::string& help) {
  std::vector<std::string> names;
  for (const HelpOption& o : help_options(help))
    if (o.values.empty()) names.push_back(o.name);
  return names;
}

}  // namespace dacrt
