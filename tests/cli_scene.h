// A small scene for the command-line tests, and the check of a refused run: exit code, one line,
// the words that name what is wrong.
#pragma once

#include <initializer_list>
#include <string>

#include "cli.h"
#include "gltf_writer.h"

namespace dacrt::test {

// A one-triangle scene with a camera (`aspect` > 0 sets its aspectRatio) in `dir`.
inline std::string small_scene(const TempDir& dir, double aspect = 0.0,
                               const std::string& name = "s.gltf") {
  GltfWriter w;
  int node = w.add_triangles({{-1, -1, -3}, {1, -1, -3}, {0, 1, -3}});
  nlohmann::json perspective = {{"yfov", 0.8}, {"znear", 0.01}};
  if (aspect > 0.0) perspective["aspectRatio"] = aspect;
  w.doc["cameras"] = {{{"type", "perspective"}, {"perspective", perspective}}};
  int camera = w.add_node({{"camera", 0}});
  w.set_scene({node, camera});
  return w.write_gltf(dir / name);
}

// The one error line of a failed run, checked: exit `code`, one line, every word in it.
inline void check_refused(const Run& r, int code, std::initializer_list<std::string> words) {
  INFO(r.err);
  CHECK(r.code == code);
  CHECK(lines(r.err) == 1);
  for (const std::string& w : words) CHECK_MESSAGE(r.err.find(w) != std::string::npos, w);
}

}  // namespace dacrt::test
