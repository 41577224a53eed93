// The channel names dacrt writes, split as Blender's and Nuke's EXR readers split them: every
// image channel lands in the pass (Blender) or layer (Nuke) it belongs to, and the exact-sum
// words land in none of them (docs/usage.md#aovs).
#include <doctest/doctest.h>

#include <cctype>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "dacrt/film/film.h"
#include "dacrt/io/film_exr.h"

using namespace dacrt;

namespace {

std::string upper(std::string s) {
  for (char& c : s) c = char(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// Where Blender puts a channel: its layer, its pass and the channel's letter.
struct BlenderChannel {
  std::string layer, pass;
  char id;
};

// Blender 3.4's imb_exr_split_channel_name (source/blender/imbuf/intern/openexr/openexr_api.cpp):
// a one-character name is a pass of the unnamed layer (R, G, B, A: "Combined"; Z: "Depth"; else
// the name). Otherwise the text after the last '.' (imb_exr_split_token) is the channel, kept only
// when it is one character, two ending in one of XYZRGBUVA ("NZ"), or red, green, blue, alpha,
// depth; the token before it is the pass, everything before that the layer. Anything else is
// dropped with "multilayer read: unknown channel token" (or "bad channel name": an empty token).
std::optional<BlenderChannel> blender_split(const std::string& name) {
  if (name.size() == 1) {
    const char c = name[0];
    const std::string pass = std::string("RGBA").find(c) != std::string::npos ? "Combined"
                             : c == 'Z'                                        ? "Depth"
                                                                               : name;
    return BlenderChannel{"", pass, char(std::toupper(static_cast<unsigned char>(c)))};
  }
  const size_t dot = name.rfind('.');
  const std::string token = dot == std::string::npos ? name : name.substr(dot + 1);
  const std::string word = upper(token);
  const std::map<std::string, char> words = {
      {"RED", 'R'}, {"GREEN", 'G'}, {"BLUE", 'B'}, {"ALPHA", 'A'}, {"DEPTH", 'Z'}};
  char id = 0;
  if (word.size() == 1)
    id = word[0];
  else if (word.size() == 2 && std::string("XYZRGBUVA").find(word[1]) != std::string::npos)
    id = word[1];
  else if (words.count(word))
    id = words.at(word);
  if (id == 0 || dot == std::string::npos || dot == 0) return std::nullopt;
  const std::string rest = name.substr(0, dot);
  const size_t before = rest.rfind('.');
  const std::string pass = before == std::string::npos ? rest : rest.substr(before + 1);
  if (pass.empty()) return std::nullopt;
  return BlenderChannel{before == std::string::npos ? "" : rest.substr(0, before), pass, id};
}

// Nuke's layer.channel for an EXR channel: validchanname in the exrReader of Nuke's NDK examples
// splits at each '.', drops the digits that begin a part and empty parts, makes other characters
// than letters and digits '_', joins all parts but the last with '_' into the layer; R/G/B/A in
// any case become red/green/blue/alpha. A name with no layer is one of Nuke's own channels (R,
// G, B: rgba; Z: depth.Z).
std::string nuke_name(const std::string& name) {
  std::vector<std::string> parts;
  for (size_t at = 0; at <= name.size();) {
    size_t end = name.find('.', at);
    if (end == std::string::npos) end = name.size();
    std::string part = name.substr(at, end - at);
    part.erase(0, part.find_first_not_of("0123456789"));
    for (char& c : part)
      if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    if (!part.empty()) parts.push_back(part);
    at = end + 1;
  }
  std::string layer;
  for (size_t k = 0; k + 1 < parts.size(); ++k) layer += (k ? "_" : "") + parts[k];
  const std::map<std::string, std::string> rgba = {
      {"R", "red"}, {"G", "green"}, {"B", "blue"}, {"A", "alpha"}};
  const std::string chan = rgba.count(upper(parts.back())) ? rgba.at(upper(parts.back()))
                                                           : parts.back();
  return layer.empty() ? chan : layer + "." + chan;
}

}  // namespace

TEST_CASE("exr names: every channel dacrt writes is in its Blender pass and Nuke layer") {
  const Film film(2, 2, AovSet::parse("albedo,normal,depth,position,variance,samples"));
  // Blender's passes: pass name → its channels' letters, in the unnamed layer.
  std::map<std::string, std::string> passes;
  std::set<std::string> nuke;
  for (const Channel& c : film.channels(true)) {
    INFO(c.name);
    const std::optional<BlenderChannel> b = blender_split(c.name);
    REQUIRE(b);
    CHECK(b->layer == "");
    passes[b->pass] += b->id;
    CHECK(nuke.insert(nuke_name(c.name)).second);  // no two channels fall together in Nuke
  }
  // Blender orders a 3-channel pass by its letters: R, G, B when one is B, X, Y, Z when one is Y.
  CHECK(passes == std::map<std::string, std::string>{{"Combined", "RGB"},
                                                     {"albedo", "RGB"},
                                                     {"N", "XYZ"},
                                                     {"Depth", "Z"},
                                                     {"P", "XYZ"},
                                                     {"variance", "RGB"},
                                                     {"samples", "X"}});
  CHECK(nuke == std::set<std::string>{"red", "green", "blue", "albedo.red", "albedo.green",
                                      "albedo.blue", "N.X", "N.Y", "N.Z", "Z", "P.X", "P.Y", "P.Z",
                                      "variance.red", "variance.green", "variance.blue",
                                      "samples.X"});

  // The exact sums: data, not images. Blender 3.4 drops every one (so none joins an image pass
  // or makes a pass of its own), and in Nuke none falls on an image channel.
  const std::vector<WordChannel> words = film_words(film);
  CHECK(words.size() == size_t(4 * film.sums_per_pixel() + 3));
  for (const WordChannel& w : words) {
    INFO(w.name);
    CHECK(w.name.rfind("exact.", 0) == 0);
    CHECK_FALSE(blender_split(w.name));
    CHECK(nuke.count(nuke_name(w.name)) == 0);
  }
}

TEST_CASE("exr names: the Blender and Nuke rules as their readers apply them") {
  // The cases the readers' sources name: Blender's own multilayer names, two-letter channels,
  // long channel words; the names Blender drops.
  auto split = [](const std::string& n) {
    const auto b = blender_split(n);
    return b ? b->layer + "|" + b->pass + "|" + b->id : std::string("dropped");
  };
  CHECK(split("ViewLayer.Combined.R") == "ViewLayer|Combined|R");
  CHECK(split("ViewLayer.Depth.Z") == "ViewLayer|Depth|Z");
  CHECK(split("Z") == "|Depth|Z");
  CHECK(split("G") == "|Combined|G");
  CHECK(split("N.NZ") == "|N|Z");
  CHECK(split("diffuse.red") == "|diffuse|R");
  CHECK(split("samples") == "dropped");
  CHECK(split("exact.count") == "dropped");
  CHECK(split("exact.sums.0.w0") == "dropped");
  CHECK(nuke_name("R") == "red");
  CHECK(nuke_name("exact.sums.12.w3") == "exact_sums.w3");
  CHECK(nuke_name("my-layer.b") == "my_layer.blue");
}

TEST_CASE("film: outputs() groups the channels by the AOV they belong to, as channels() orders them") {
  const AovSet every = AovSet::parse("albedo,normal,depth,position,variance,samples");
  Film film(2, 1, every);
  const std::vector<Film::Output> outputs = film.outputs();
  std::vector<std::string> names, flat;
  for (const Film::Output& o : outputs) {
    names.push_back(o.name);
    for (const Channel& c : o.channels) flat.push_back(c.name);
  }
  CHECK(names == std::vector<std::string>{"", "albedo", "normal", "depth", "position",
                                          "variance", "samples"});
  std::vector<std::string> channels;
  for (const Channel& c : film.channels()) channels.push_back(c.name);
  CHECK(flat == channels);
  CHECK(outputs[3].channels.size() == 1);  // depth: Z
  CHECK(outputs[2].channels[0].name == "N.X");
  // The per-pixel counts alone (a render cut short) are the samples output too.
  const std::vector<Film::Output> cut = Film(2, 1, AovSet::parse("depth")).outputs(true);
  REQUIRE(cut.size() == 3);
  CHECK(cut[2].name == "samples");
}
