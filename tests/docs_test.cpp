// The docs against the code they describe: docs/usage.md must name every option the CLI's --help
// prints, in the section of the command that prints it, and nothing the CLI no longer has; its
// table of dacrt backend keys must be the keys `render --help` and `bench --help` list; every
// relative link in README.md and docs/*.md must lead to a file (and heading) that exists; and
// docs/architecture.md's source tree must name every file of the code's folders and no file
// that is not there.
#include <doctest/doctest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli.h"
#include "help_text.h"

using namespace dacrt::test;
namespace fs = std::filesystem;

namespace {

const fs::path source_dir = DACRT_SOURCE_DIR;

// The section of usage.md under "## dacrt COMMAND", up to the next "## " heading.
std::string section(const std::string& usage, const std::string& command) {
  const std::string heading = "## dacrt " + command + "\n";
  const size_t start = usage.find(heading);
  if (start == std::string::npos) return "";
  const size_t end = usage.find("\n## ", start + heading.size());
  return usage.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

// The rows of the markdown tables in `text` (lines starting with "|").
std::string table_rows(const std::string& text) {
  std::string rows;
  for (const std::string& line : lines_of(text))
    if (line.rfind("|", 0) == 0) rows += line + "\n";
  return rows;
}

// The cells of one table row, trimmed: "| a | b |" gives {"a", "b"}.
std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  size_t at = 1;
  for (size_t bar = row.find('|', at); bar != std::string::npos; bar = row.find('|', at)) {
    std::string cell = row.substr(at, bar - at);
    cell.erase(0, cell.find_first_not_of(' '));
    cell.erase(cell.find_last_not_of(' ') + 1);
    out.push_back(cell);
    at = bar + 1;
  }
  return out;
}

// The comma-separated keys a help text lists after `marker` up to the closing parenthesis:
// "(dacrt: bins, leaf_rays, ...)" in `render --help`, "(keys: bins, ...)" in `bench --help`.
Names keys_after(const std::string& help, const std::string& marker) {
  Names keys;
  const size_t start = help.find(marker);
  if (start == std::string::npos) return keys;
  const size_t end = help.find(')', start);
  std::string key;
  for (size_t i = start + marker.size(); i < end; ++i) {
    const char c = help[i];
    if (std::islower(static_cast<unsigned char>(c)) || c == '_') {
      key += c;
    } else if (!key.empty()) {
      keys.insert(key);
      key.clear();
    }
  }
  if (!key.empty()) keys.insert(key);
  return keys;
}

// The keys of usage.md's backend key table: the rows under a "| key |" header, first cell `key`.
Names documented_keys(const std::string& usage, bool& every_row_described) {
  Names keys;
  every_row_described = true;
  bool in_table = false;
  for (const std::string& line : lines_of(usage)) {
    if (line.rfind("| key |", 0) == 0) {
      in_table = true;
      continue;
    }
    if (line.rfind("|", 0) != 0) {
      in_table = false;
      continue;
    }
    if (!in_table || line.rfind("|---", 0) == 0) continue;
    const std::vector<std::string> row = cells(line);
    if (row.size() < 3 || row[0].size() < 3 || row[0].front() != '`' || row[0].back() != '`') {
      every_row_described = false;
      continue;
    }
    keys.insert(row[0].substr(1, row[0].size() - 2));
    every_row_described &= !row[2].empty();
  }
  return keys;
}

// GitHub's anchor for a heading: lower case, spaces to '-', ASCII punctuation but '-' and '_'
// dropped (other characters kept as they are).
std::string anchor_of(const std::string& heading) {
  std::string anchor;
  for (const char c : heading) {
    const auto u = static_cast<unsigned char>(c);
    if (c == ' ')
      anchor += '-';
    else if (u >= 0x80 || std::isalnum(u) || c == '-' || c == '_')
      anchor += char(std::tolower(u));
  }
  return anchor;
}

Names anchors_of(const std::string& markdown) {
  Names anchors;
  bool fenced = false;
  for (const std::string& line : lines_of(markdown)) {
    if (line.rfind("```", 0) == 0) fenced = !fenced;
    if (fenced || line.empty() || line[0] != '#') continue;
    const size_t text = line.find_first_not_of('#');
    if (text == std::string::npos || line[text] != ' ') continue;
    anchors.insert(anchor_of(line.substr(text + 1)));
  }
  return anchors;
}

// The targets of the inline links and images in `markdown` ("](target)"), outside code blocks.
std::vector<std::string> link_targets(const std::string& markdown) {
  std::vector<std::string> targets;
  bool fenced = false;
  for (const std::string& line : lines_of(markdown)) {
    if (line.rfind("```", 0) == 0) fenced = !fenced;
    if (fenced) continue;
    for (size_t at = line.find("]("); at != std::string::npos; at = line.find("](", at + 2)) {
      const size_t end = line.find(')', at + 2);
      if (end != std::string::npos) targets.push_back(line.substr(at + 2, end - at - 2));
    }
  }
  return targets;
}

}  // namespace

TEST_CASE("docs: usage.md names every option of every --help, and no other") {
  const std::string usage = slurp(source_dir / "docs" / "usage.md");
  REQUIRE(!usage.empty());
  const std::vector<Help> all = helps();

  Names printed;  // every option some --help prints
  for (const Help& h : all) {
    const Names options = printed_options(h.text);
    printed.insert(options.begin(), options.end());
  }
  // The parsing finds what it should (else the checks below would pass on nothing).
  for (const char* known : {"--backend-option", "--tmax-at-hit", "--reference-spp", "-o", "-h"})
    CHECK_MESSAGE(printed.count(known), known << " is not found in any --help");
  CHECK(defined_options(help_of(all, "render")).count("--height"));
  // (converge's prose names it, not one of its own lines)
  CHECK(!defined_options(help_of(all, "converge")).count("--look-from"));

  // Each command has its section. The options its help defines are in the section's tables;
  // every option its help prints is named in the section (the top level's: in the page).
  for (const Help& h : all) {
    const std::string where = h.command.empty() ? usage : section(usage, h.command);
    CHECK_MESSAGE(!where.empty(), "usage.md has no section \"## dacrt " << h.command << "\"");
    for (const std::string& option : printed_options(h.text))
      CHECK_MESSAGE(has_token(where, option), "dacrt " << h.command << " --help prints " << option
                                                       << ", which usage.md does not name there");
    if (h.command.empty()) continue;
    const std::string tables = table_rows(where);
    for (const std::string& option : defined_options(h.text))
      CHECK_MESSAGE(has_token(tables, option), "dacrt " << h.command << " --help has " << option
                                                        << ", which no table of its section has");
  }
  for (const std::string& line : lines_of(all.front().text)) {
    const std::string prefix = "  dacrt ";
    if (line.rfind(prefix, 0) != 0 || line.size() <= prefix.size() || line[prefix.size()] == '-')
      continue;
    const std::string command =
        line.substr(prefix.size(), line.find(' ', prefix.size()) - prefix.size());
    CHECK_MESSAGE(!section(usage, command).empty(),
                  "dacrt --help lists " << command << ", usage.md has no section for it");
  }

  // Nothing in usage.md that the CLI does not print: a removed option cannot linger. The options
  // in a command's tables are that command's own.
  for (const std::string& option : long_options(usage))
    CHECK_MESSAGE(printed.count(option), "usage.md names " << option << ", which no --help prints");
  for (const Help& h : all) {
    if (h.command.empty()) continue;
    const Names own = printed_options(h.text);
    for (const std::string& option : long_options(table_rows(section(usage, h.command))))
      CHECK_MESSAGE(own.count(option), "usage.md's tables for dacrt "
                                           << h.command << " name " << option
                                           << ", which its --help does not print");
  }
}

TEST_CASE("docs: usage.md describes every dacrt backend key the help lists") {
  const std::string usage = slurp(source_dir / "docs" / "usage.md");
  const std::vector<Help> all = helps();
  const Names render_keys = keys_after(help_of(all, "render"), "(dacrt:");
  const Names bench_keys = keys_after(help_of(all, "bench"), "(keys:");
  CHECK(render_keys.size() >= 10);
  CHECK(render_keys.count("bins"));
  CHECK(render_keys.count("group_rays"));
  CHECK(render_keys == bench_keys);

  bool every_row_described = false;
  const Names documented = documented_keys(usage, every_row_described);
  CHECK_MESSAGE(every_row_described, "a row of usage.md's key table has no key or description");
  for (const std::string& key : render_keys)
    CHECK_MESSAGE(documented.count(key), "render --help lists the dacrt key " << key
                                                                              << ", usage.md's key "
                                                                              << "table has no row "
                                                                              << "for it");
  for (const std::string& key : documented)
    CHECK_MESSAGE(render_keys.count(key), "usage.md's key table has " << key
                                                                      << ", which render --help "
                                                                      << "does not list");
}

TEST_CASE("docs: every relative link in README.md and docs/*.md leads to a file and heading") {
  std::vector<fs::path> pages = {source_dir / "README.md"};
  for (const auto& entry : fs::directory_iterator(source_dir / "docs"))
    if (entry.path().extension() == ".md") pages.push_back(entry.path());
  std::sort(pages.begin(), pages.end());
  REQUIRE(pages.size() >= 2);

  size_t relative = 0;
  for (const fs::path& page : pages) {
    const std::string text = slurp(page);
    for (const std::string& target : link_targets(text)) {
      if (target.find("://") != std::string::npos || target.rfind("mailto:", 0) == 0) continue;
      ++relative;
      const size_t hash = target.find('#');
      const std::string file = target.substr(0, hash);
      const fs::path to = file.empty() ? page : page.parent_path() / file;
      INFO(page.filename().string() << " links to " << target);
      CHECK_MESSAGE(fs::is_regular_file(to), "no such file: " << to.string());
      if (hash == std::string::npos || !fs::is_regular_file(to) || to.extension() != ".md")
        continue;
      const std::string anchor = target.substr(hash + 1);
      CHECK_MESSAGE(anchors_of(slurp(to)).count(anchor), "no heading with the anchor #" << anchor);
    }
  }
  CHECK(relative >= 10);  // the links were found at all
}

namespace {

// docs/architecture.md's source tree: each folder's entry ("name/" at the line's start, or
// indented for a subfolder) and the text that describes it, up to the next entry.
std::vector<std::pair<std::string, std::string>> tree_entries(const std::string& page) {
  std::vector<std::pair<std::string, std::string>> entries;
  bool in_block = false;
  std::string parent;
  for (const std::string& line : lines_of(page)) {
    if (line.rfind("```", 0) == 0) {
      if (in_block && !entries.empty()) break;  // the end of the tree's block
      in_block = true;
      continue;
    }
    if (!in_block) continue;
    const size_t indent = line.find_first_not_of(' ');
    if (indent == std::string::npos) continue;
    const size_t slash = line.find('/', indent);
    const bool entry = (indent == 0 || indent == 2) && slash != std::string::npos &&
                       std::all_of(line.begin() + long(indent), line.begin() + long(slash),
                                   word_char);
    if (entry) {
      const std::string name = line.substr(indent, slash - indent);
      if (indent == 0) parent = name;
      entries.push_back({indent == 0 ? name : parent + "/" + name, line.substr(slash + 1)});
    } else if (!entries.empty()) {
      entries.back().second += " " + line;
    }
  }
  return entries;
}

// The file names a description writes with a source file's extension ("a.h", "b.{h,cpp}",
// "c.py"), braces expanded.
Names named_files(const std::string& text) {
  Names names;
  for (size_t i = 0; i < text.size();) {
    if (!word_char(text[i]) || (i > 0 && (word_char(text[i - 1]) || text[i - 1] == '.'))) {
      ++i;
      continue;
    }
    size_t j = i;
    while (j < text.size() && word_char(text[j])) ++j;
    const std::string stem = text.substr(i, j - i);
    if (j + 1 < text.size() && text[j] == '.' && text[j + 1] == '{') {
      const size_t close = text.find('}', j);
      std::istringstream list(text.substr(j + 2, close - j - 2));
      for (std::string ext; std::getline(list, ext, ',');) names.insert(stem + "." + ext);
      i = close + 1;
    } else if (j + 1 < text.size() && text[j] == '.' && std::isalpha(uint8_t(text[j + 1]))) {
      size_t k = j + 1;
      while (k < text.size() && std::isalnum(uint8_t(text[k]))) ++k;
      // (Only a source file's extensions: "library.md" is a link, "match.inputs" a key.)
      static const Names kinds = {"h", "cpp", "py", "sh", "dict"};
      if (kinds.count(text.substr(j + 1, k - j - 1))) names.insert(text.substr(i, k - i));
      i = k;
    } else {
      i = j;
    }
  }
  return names;
}

}  // namespace

TEST_CASE("docs: architecture.md's source tree names every file of the code's folders, and only "
          "files that exist") {
  const auto entries = tree_entries(slurp(source_dir / "docs" / "architecture.md"));
  REQUIRE(entries.size() >= 15);
  std::map<std::string, std::string> text;
  for (const auto& [folder, description] : entries) text[folder] += " " + description;
  // Every folder of code is in the tree.
  for (const char* folder : {"util", "materials", "tracer", "tracer/dacrt", "scene", "film", "io",
                             "io/gltf", "integrators", "render", "bench", "apps", "python",
                             "fuzz", "tools", "examples", "tests", "blender"}) {
    INFO(std::string(folder));
    CHECK(text.count(folder));
  }
  // Each file a description names with its extension exists in that folder.
  for (const auto& [folder, description] : text)
    for (const std::string& name : named_files(description)) {
      if (folder == "tests" || folder == "blender") break;  // (described by kind)
      INFO(folder << "/ names " << name);
      CHECK(fs::exists(source_dir / folder / name));
    }
  // Each source file of the code's folders is named, with its extension or by its stem.
  for (const char* folder : {"util", "materials", "tracer", "tracer/dacrt", "scene", "film", "io",
                             "io/gltf", "integrators", "render", "bench", "apps", "python",
                             "fuzz", "tools", "examples"}) {
    const std::string& description = text[folder];
    for (const fs::directory_entry& file : fs::directory_iterator(source_dir / folder)) {
      if (!file.is_regular_file()) continue;
      const std::string name = file.path().filename().string();
      const std::string stem = file.path().stem().string();
      auto said = [&](const std::string& word) {
        for (size_t at = description.find(word); at != std::string::npos;
             at = description.find(word, at + 1)) {
          const size_t end = at + word.size();
          if ((at == 0 || !word_char(description[at - 1])) &&
              (end == description.size() || !word_char(description[end])))
            return true;
        }
        return false;
      };
      INFO(std::string(folder) << "/" << name << " is not in architecture.md's tree");
      CHECK((named_files(description).count(name) || said(stem)));
    }
  }
}
