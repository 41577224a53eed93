// Text from outside (file names, names inside a scene) made fit for where it goes: valid UTF-8
// for JSON, one bounded line for a message.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace dacrt {

// `text` with every byte that is not part of a well-formed UTF-8 sequence (RFC 3629: no overlong
// forms, no surrogates, nothing above U+10FFFF) written as the four characters "\xNN": valid
// UTF-8 that still shows what the bytes were. Valid text is returned unchanged.
inline std::string valid_utf8(std::string_view text) {
  static const char hex[] = "0123456789ABCDEF";
  std::string out;
  out.reserve(text.size());
  const auto byte = [&](size_t i) { return uint8_t(text[i]); };
  for (size_t i = 0; i < text.size();) {
    const uint8_t c = byte(i);
    size_t n = 0;                  // continuation bytes
    uint8_t lo = 0x80, hi = 0xBF;  // the second byte's range
    if (c < 0x80)
      n = 0;
    else if (c >= 0xC2 && c <= 0xDF)
      n = 1;
    else if (c >= 0xE0 && c <= 0xEF)
      n = 2, lo = c == 0xE0 ? 0xA0 : 0x80, hi = c == 0xED ? 0x9F : 0xBF;
    else if (c >= 0xF0 && c <= 0xF4)
      n = 3, lo = c == 0xF0 ? 0x90 : 0x80, hi = c == 0xF4 ? 0x8F : 0xBF;
    else
      n = SIZE_MAX;
    bool ok = n != SIZE_MAX && i + n < text.size();
    for (size_t k = 1; ok && k <= n; ++k) {
      const uint8_t b = byte(i + k);
      ok = k == 1 ? b >= lo && b <= hi : b >= 0x80 && b <= 0xBF;
    }
    if (ok) {
      out.append(text.substr(i, n + 1));
      i += n + 1;
    } else {
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
      i += 1;
    }
  }
  return out;
}

// A message made one line of at most `max_chars` bytes: line breaks and other control characters
// become spaces, and a longer text keeps its start and its end around " … " (a quoted argument of
// any length cannot push the part that says what is wrong off the line).
inline std::string message_line(std::string_view text, size_t max_chars = 999) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) out += (uint8_t(c) < 0x20 || c == 0x7F) ? ' ' : c;
  while (!out.empty() && out.back() == ' ') out.pop_back();
  if (out.size() <= max_chars) return out;
  const std::string_view gap = " ... ";
  const size_t keep = max_chars - gap.size(), head = keep / 2, tail = keep - head;
  return out.substr(0, head) + std::string(gap) + out.substr(out.size() - tail);
}

// Writes `text` to stderr as one message line (message_line). Best-effort: a closed stderr loses
// the message, nothing else.
inline void print_message(std::string_view text) {
  const std::string line = message_line(text);
  std::fprintf(stderr, "%s\n", line.c_str());
}

// A JSON document as text, with every string in it (keys too) made valid UTF-8 by valid_utf8:
// nlohmann::json refuses to print invalid UTF-8, and a scene may be named in any bytes. `Json` is
// nlohmann::json (a template so that this header does not need it).
template <class Json>
void make_valid_utf8(Json& j) {
  if (j.is_string()) {
    j = valid_utf8(j.template get_ref<const std::string&>());
  } else if (j.is_array()) {
    for (auto& item : j) make_valid_utf8(item);
  } else if (j.is_object()) {
    Json fixed = Json::object();
    for (auto it = j.begin(); it != j.end(); ++it) {
      Json value = it.value();
      make_valid_utf8(value);
      fixed[valid_utf8(it.key())] = std::move(value);
    }
    j = std::move(fixed);
  }
}
template <class Json>
std::string json_text(Json j, int indent = 2) {
  make_valid_utf8(j);
  return j.dump(indent);
}

// The number of single-character insertions, deletions and substitutions that make `a` into
// `b` (Levenshtein).
inline size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// " (did you mean NAME?)" for the name of `known` nearest to `given`, when it is within two
// edits (one for names of three characters or fewer) and not `given` itself, or else the one
// name that begins with `given`; "" when there is none.
inline std::string did_you_mean(std::string_view given, const std::vector<std::string>& known) {
  const size_t most = given.size() <= 3 ? 1 : 2;
  std::string best;
  size_t fewest = most + 1, starting = 0;
  for (const std::string& k : known)
    if (const size_t n = edit_distance(given, k); n > 0 && n < fewest) fewest = n, best = k;
  if (best.empty() && given.size() >= 2)
    for (const std::string& k : known)
      if (k.size() > given.size() && k.compare(0, given.size(), given) == 0) ++starting, best = k;
  if (starting > 1) best.clear();
  return best.empty() ? "" : " (did you mean " + best + "?)";
}

}  // namespace dacrt
