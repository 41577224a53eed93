// The bash completion script and the manual page (see completion.h).
#include "apps/completion.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <sstream>

#include "dacrt/render/request.h"
#include "dacrt/util/help_text.h"

namespace dacrt {

namespace {

// The arguments a command's "Usage:" line shows that are not options nor their values
// ("SCENE", "PART.exr...", "A.exr", "bash").
std::vector<std::string> positionals(const std::string& help) {
  std::vector<std::string> out;
  for (const std::string& line : text_lines(help)) {
    if (line.rfind("Usage: dacrt ", 0) != 0) continue;
    const std::vector<std::string> words = text_words(line);
    for (size_t k = 3; k < words.size(); ++k) {
      const std::string& w = words[k];
      if (w[0] == '[') break;  // optional parts: options
      if (is_option_word(w)) {
        ++k;
        continue;
      }
      out.push_back(w);
    }
  }
  return out;
}

// How the completion offers an option's value (or a positional argument).
struct ValueKind {
  enum Kind { none, files, dirs, words, list, views } kind = none;
  std::string what;  // files: "exr|EXR" ("" any); words and list: the words, space-separated
};

// What a value as a help shows it ("OUT.exr", "SCENE", "DIR", "rays", "NAME|INDEX|all") asks for.
ValueKind kind_of(const std::string& shown) {
  std::string v = shown;
  if (v.size() > 3 && v.compare(v.size() - 3, 3, "...") == 0) v.resize(v.size() - 3);
  const auto ends = [&](const char* ext) {
    const std::string e = ext;
    return v.size() > e.size() && v.compare(v.size() - e.size(), e.size(), e) == 0;
  };
  if (v == "SCENE" || ends(".gltf") || ends(".glb")) return {ValueKind::files, "gltf|glb|GLTF|GLB"};
  for (const char* ext : {".exr", ".png", ".json", ".csv"})
    if (ends(ext)) {
      std::string e = ext + 1, upper = e;
      for (char& c : upper) c = char(std::toupper(static_cast<unsigned char>(c)));
      return {ValueKind::files, e + "|" + upper};
    }
  if (v == "FILE") return {ValueKind::files, ""};
  if (v == "DIR" || v == "OUTDIR") return {ValueKind::dirs, ""};
  // Literal words: "rays", "bash", the lower-case ones of "NAME|INDEX|all".
  std::string words;
  std::istringstream alternatives(v);
  for (std::string w; std::getline(alternatives, w, '|');)
    if (!w.empty() && std::all_of(w.begin(), w.end(), [](char c) {
          return std::islower(static_cast<unsigned char>(c)) || c == '-';
        }))
      words += (words.empty() ? "" : " ") + w;
  if (!words.empty()) return {ValueKind::words, words};
  return {};
}

std::string joined(const std::vector<std::string>& words, const char* between = " ") {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "" : between) + w;
  return out;
}

// What completes the value of option `o` of a command: the option table's knowledge for a render
// option (its choices, its value type), else what its help shows.
ValueKind value_kind(const HelpOption& o) {
  if (o.name == "--view") return {ValueKind::views, ""};
  const std::vector<std::string> choices = render_option_choices(o.name);
  if (const RenderOption* r = find_render_option(o.name); r && !choices.empty())
    return {r->value == OptionValue::names ? ValueKind::list : ValueKind::words, joined(choices)};
  ValueKind kind;
  for (const std::string& v : o.values) {
    const ValueKind k = kind_of(v);
    if (k.kind == ValueKind::words && kind.kind == ValueKind::words)
      kind.what += " " + k.what;
    else if (k.kind != ValueKind::none && kind.kind == ValueKind::none)
      kind = k;
  }
  return kind;
}

// A bash single-quoted word.
std::string quoted(const std::string& text) {
  std::string q = "'";
  for (char c : text) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string action(const ValueKind& k) {
  switch (k.kind) {
    case ValueKind::files: return "_dacrt__files " + quoted(k.what);
    case ValueKind::dirs: return "_dacrt__dirs";
    case ValueKind::words: return "_dacrt__words " + quoted(k.what);
    case ValueKind::list: return "_dacrt__list " + quoted(k.what);
    case ValueKind::views: return "_dacrt__views";
    case ValueKind::none: break;
  }
  return ":";  // a number or a name of the scene: nothing to offer
}

// The options of command `c`: those its help defines, --help, and for render and converge every render
// option they take from the option table (converge's help names them in its prose only).
std::vector<HelpOption> command_options(const CommandHelp& c) {
  std::vector<HelpOption> options = help_options(c.help);
  add_help_option(options, "--help", "-h", "");  // every command takes it, though not every help says
  const unsigned use = c.name == "render"     ? unsigned(use_render)
                       : c.name == "converge" ? unsigned(use_converge)
                                              : 0u;
  if (use) {
    const std::vector<HelpOption> from_help = help_options(render_help());
    for (const RenderOption& r : render_options()) {
      if (!(r.uses & use)) continue;
      const std::string name(r.name);
      const auto shown = std::find_if(from_help.begin(), from_help.end(),
                                      [&](const HelpOption& h) { return h.name == name; });
      if (shown == from_help.end() || r.value == OptionValue::none)
        add_help_option(options, name, std::string(r.short_name), "");
      else
        for (const std::string& v : shown->values)
          add_help_option(options, name, std::string(r.short_name), v);
    }
  }
  return options;
}

std::string function_name(const std::string& command) {
  std::string f = "_dacrt_command_" + command;
  std::replace(f.begin(), f.end(), '-', '_');
  return f;
}

constexpr const char* completion_head = R"bash(# bash completion for dacrt: commands, their options, the values the option table knows,
# display views (from `dacrt views`) and file names by extension. Made by `dacrt completion bash`.
# Load it with `source <(dacrt completion bash)`, or install it as
# share/bash-completion/completions/dacrt.

# File names among $cur with one of the extensions $1 ("exr|EXR"; "" for any), and folders.
_dacrt__files() {
  local f IFS=$'\n'
  compopt -o filenames 2>/dev/null
  COMPREPLY=()
  for f in $(compgen -f -- "$cur"); do
    if [[ -d $f || -z $1 ]] || [[ $f =~ \.($1)$ ]]; then COMPREPLY+=("$f"); fi
  done
}
_dacrt__dirs() {
  local IFS=$'\n'
  compopt -o filenames 2>/dev/null
  COMPREPLY=($(compgen -d -- "$cur"))
}
# One of the words $1.
_dacrt__words() {
  COMPREPLY=($(compgen -W "$1" -- "$cur"))
}
# A comma-separated list of the words $1: the item after the last comma.
_dacrt__list() {
  local prefix="" item=$cur
  if [[ $cur == *,* ]]; then prefix=${cur%,*},; item=${cur##*,}; fi
  COMPREPLY=($(compgen -P "$prefix" -W "$1" -- "$item"))
}
# A display view, as `dacrt views` lists them (names with spaces come back quoted).
_dacrt__views() {
  local v want=${cur//\\/} dacrt=${COMP_WORDS[0]/#\~/$HOME}
  want=${want#[\"\']}
  COMPREPLY=()
  while IFS= read -r v; do
    v=${v% (default)}
    [[ $v == "$want"* ]] && COMPREPLY+=("$(printf '%q' "$v")")
  done < <("$dacrt" views 2>/dev/null)
}
)bash";

}  // namespace

std::string bash_completion(const std::vector<CommandHelp>& commands) {
  std::string script = completion_head;
  std::vector<std::string> names;
  for (const CommandHelp& c : commands) {
    names.push_back(c.name);
    const std::vector<HelpOption> options = command_options(c);
    std::vector<std::string> words;
    script += "\n# dacrt " + c.name + "\n" + function_name(c.name) + "() {\n  case $prev in\n";
    for (const HelpOption& o : options) {
      words.push_back(o.name);
      if (!o.short_name.empty()) words.push_back(o.short_name);
      if (o.values.empty()) continue;  // a flag
      script += "    " + (o.short_name.empty() ? "" : o.short_name + "|") + o.name + ") " +
                action(value_kind(o)) + "; return ;;\n";
    }
    script += "  esac\n  if [[ $cur == -* ]]; then\n    _dacrt__words " + quoted(joined(words)) +
              "\n    return\n  fi\n";
    const std::vector<std::string> args = positionals(c.help);
    script += "  " + (args.empty() ? std::string("COMPREPLY=()") : action(kind_of(args.front()))) +
              "\n}\n";
  }
  script += R"bash(
_dacrt() {
  local cur=${COMP_WORDS[COMP_CWORD]} prev=
  (( COMP_CWORD > 0 )) && prev=${COMP_WORDS[COMP_CWORD-1]}
  # --option=value: bash splits the word at '='.
  if [[ $cur == = ]]; then
    cur=
  elif [[ $prev == = ]] && (( COMP_CWORD > 1 )); then
    prev=${COMP_WORDS[COMP_CWORD-2]}
  fi
  if (( COMP_CWORD == 1 )); then
)bash";
  script += "    _dacrt__words " + quoted(joined(names) + " --help --version") +
            "\n    return\n  fi\n  case ${COMP_WORDS[1]} in\n";
  for (const CommandHelp& c : commands)
    script += "    " + c.name + ") " + function_name(c.name) + " ;;\n";
  script += "    *) COMPREPLY=() ;;\n  esac\n}\ncomplete -F _dacrt dacrt\n";
  return script;
}

// ----------------------------------------------------------------------------------------------
// The manual page.

namespace {

// Text for roff: backslashes, hyphens as the minus sign options need, non-ASCII characters as
// groff's \[uXXXX], a control character at a line's start kept as text.
std::string roff(const std::string& text) {
  std::string out;
  for (size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == '\\') {
      out += "\\e";
    } else if (c == '-') {
      out += "\\-";
    } else if (c < 0x80) {
      out += char(c);
    } else {
      // UTF-8: the code point of a 2-, 3- or 4-byte sequence.
      const int n = c >= 0xF0 ? 3 : c >= 0xE0 ? 2 : 1;
      uint32_t cp = c & (0x3Fu >> n);
      for (int k = 0; k < n && i + 1 < text.size(); ++k) cp = cp << 6 | (uint8_t(text[++i]) & 0x3F);
      char buf[16];
      std::snprintf(buf, sizeof buf, "\\[u%04X]", unsigned(cp));
      out += buf;
    }
  }
  return out;
}

// A roff text line: no leading spaces, nothing a request could be taken for.
std::string text_line(const std::string& line) {
  const std::string t = roff(line.substr(std::min(line.size(), line.find_first_not_of(' '))));
  return (!t.empty() && (t[0] == '.' || t[0] == '\'') ? "\\&" : "") + t + "\n";
}

// An item's term: options bold, placeholders (capitalised) italic.
std::string term(const std::string& column) {
  std::string out;
  for (const std::string& w : text_words(column)) {
    const size_t letter = w.find_first_not_of("[\"(");
    const bool option = letter != std::string::npos && w[letter] == '-';
    const bool placeholder =
        letter != std::string::npos && std::isupper(static_cast<unsigned char>(w[letter]));
    if (!out.empty()) out += ' ';
    const char* font = option || w == "dacrt" ? "\\fB" : placeholder ? "\\fI" : "";
    out.append(font).append(roff(w)).append(*font ? "\\fR" : "");
  }
  if (!out.empty() && (out[0] == '.' || out[0] == '\'')) out.insert(0, "\\&");
  out += '\n';
  return out;
}

size_t indent_of(const std::string& line) {
  const size_t at = line.find_first_not_of(' ');
  return at == std::string::npos ? line.size() : at;
}

// A help text as roff: "Usage:" lines as they are, headings bold, the indented items ("  --spp N
// samples ...", "  primary    the scene's ...") as tagged paragraphs, prose filled.
std::string help_roff(const std::string& help) {
  const std::vector<std::string> lines = text_lines(help);
  std::string out;
  enum { none, prose, item } block = none;
  for (size_t i = 0; i < lines.size(); ++i) {
    const std::string& line = lines[i];
    const size_t at = indent_of(line);
    const bool next_indented = i + 1 < lines.size() && !lines[i + 1].empty() &&
                               indent_of(lines[i + 1]) > 0;
    if (line.find_first_not_of(' ') == std::string::npos) {
      block = none;
    } else if (line.rfind("Usage:", 0) == 0) {
      out += ".PP\n.nf\n" + text_line(line);
      // Its continuation (the top level's command list is items, not this).
      while (i + 1 < lines.size() && indent_of(lines[i + 1]) > 8 &&
             lines[i + 1].find_first_not_of(' ') != std::string::npos)
        out += text_line("  " + lines[++i]);
      out += ".fi\n";
      block = none;
    } else if (at > 0 && at <= 4 && (line.find("  ", at) != std::string::npos ||
                                     (i + 1 < lines.size() && indent_of(lines[i + 1]) > at + 4 &&
                                      indent_of(lines[i + 1]) < lines[i + 1].size()))) {
      // An item: its term, then its description, on this line and the more indented ones. The
      // description starts at the column its continuation lines start at, when it is there
      // (a term that fills its column leaves one space: "  --animation NAME|INDEX|all which").
      std::string column = item_column(line, at);
      const size_t next = i + 1 < lines.size() ? indent_of(lines[i + 1]) : 0;
      if (next > at + 4 && next < line.size() && next < at + column.size() &&
          line[next - 1] == ' ' && line[next] != ' ')
        column = line.substr(at, next - 1 - at);
      out += ".TP\n" + term(column);
      const size_t rest = line.find_first_not_of(' ', at + column.size());
      if (rest != std::string::npos) out += text_line(line.substr(rest));
      while (i + 1 < lines.size() && indent_of(lines[i + 1]) > at + 4 &&
             indent_of(lines[i + 1]) < lines[i + 1].size())
        out += text_line(lines[++i]);
      block = item;
    } else if (at == 0 && next_indented && line.back() != '.' && line.size() < 80) {
      out += ".PP\n.B " + roff(line) + "\n";  // a heading of the items below it
      block = none;
    } else {
      if (block != prose) out += at > 0 ? ".IP\n" : ".PP\n";
      out += text_line(line);
      block = prose;
    }
  }
  return out;
}

}  // namespace

std::string man_page(const std::string& main_help, const std::vector<CommandHelp>& commands,
                     const std::string& version) {
  // "dacrt: a path tracer ..." as the NAME line, the rest as the synopsis and command list.
  const size_t colon = main_help.find(": ");
  const size_t eol = main_help.find('\n');
  const std::string summary =
      colon < eol ? main_help.substr(colon + 2, eol - colon - 2) : std::string("a path tracer");
  std::string page = ".\\\" dacrt(1), made by `dacrt man` from the commands' --help.\n";
  page += ".TH DACRT 1 \"\" \"dacrt " + roff(version) + "\" \"User Commands\"\n.nh\n.ad l\n";
  page += ".SH NAME\ndacrt \\- " + roff(summary) + "\n.SH SYNOPSIS\n";
  for (const CommandHelp& c : commands) {
    // The Usage line of each command, without "Usage: ".
    for (const std::string& line : text_lines(c.help))
      if (line.rfind("Usage: ", 0) == 0) {
        page += ".br\n" + term(line.substr(7));
        break;
      }
  }
  page += ".SH DESCRIPTION\n" + help_roff(main_help.substr(eol == std::string::npos ? 0 : eol + 1));
  page += ".SH COMMANDS\n";
  for (const CommandHelp& c : commands) page += ".SS dacrt " + c.name + "\n" + help_roff(c.help);
  page += R"roff(.SH EXIT STATUS
.TP
0
success
.TP
1
an error: one line on standard error names the file or option and what is wrong
.TP
2
a usage error (an unknown or misspelt option, a bad value); the line points to the command's
\fB\-\-help\fR
.TP
130, 143
a render stopped by SIGINT or SIGTERM, its outputs written
.SH ENVIRONMENT
.TP
.B OCIO
an OpenColorIO config for the previews' display views (\fBdacrt views\fR lists them)
.SH SEE ALSO
\fBdacrt \-\-help\fR, \fBdacrt\fR \fIcommand\fR \fB\-\-help\fR;
\fBsource <(dacrt completion bash)\fR for completion in bash
)roff";
  return page;
}

}  // namespace dacrt
