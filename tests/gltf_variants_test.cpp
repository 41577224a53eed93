// KHR_materials_variants: `--variant NAME` renders the materials a variant maps the primitives
// to; `dacrt info` lists the variants; a name the file does not have is a usage error naming
// those it has, and broken mappings are schema errors naming the element.
#include <doctest/doctest.h>

#include <string>

#include "dacrt/io/gltf.h"
#include "dacrt/util/error.h"
#include "tests/cli.h"
#include "tests/gltf_check.h"
#include "tests/gltf_triangle.h"
#include "tests/gltf_writer.h"
#include "tests/texture_fixtures.h"

using namespace dacrt;
using namespace dacrt::test;
using nlohmann::json;

namespace {

// One triangle of material 0 (red), mapped to material 1 (blue) by variant "blue" and to material
// 2 (green) by "green" and "also green".
GltfWriter variants_file() {
  GltfWriter w;
  w.doc["extensionsUsed"] = {"KHR_materials_variants"};
  w.doc["extensions"]["KHR_materials_variants"]["variants"] = {
      {{"name", "blue"}}, {{"name", "green"}}, {{"name", "also green"}}};
  for (const auto& rgb : {json{1, 0, 0, 1}, json{0, 0, 1, 1}, json{0, 1, 0, 1}})
    w.add_material({{"pbrMetallicRoughness", {{"baseColorFactor", rgb}}}});
  const json mappings = {{{"material", 1}, {"variants", {0}}},
                         {{"material", 2}, {"variants", {1, 2}}}};
  w.add_triangles(
      kTriangle,
      {{"material", 0}, {"extensions", {{"KHR_materials_variants", {{"mappings", mappings}}}}}});
  return w;
}

}  // namespace

TEST_CASE("KHR_materials_variants: a variant picks the materials its mappings name") {
  TempDir dir("gltf-variants");
  const std::string path = variants_file().write_gltf(dir / "variants.gltf");
  const Scene plain = load_gltf(path);
  CHECK(plain.variants == std::vector<std::string>{"blue", "green", "also green"});
  CHECK(plain.geometry.material[0] == 0u);
  CHECK(plain.variant.empty());
  for (const auto& [name, material] : {std::pair{"blue", 1u}, {"green", 2u}, {"also green", 2u}}) {
    GltfOptions o;
    o.variant = name;
    const Scene scene = load_gltf(path, o);
    CHECK(scene.geometry.material[0] == material);
    CHECK(scene.variant == name);
  }
  GltfOptions purple;
  purple.variant = "purple";
  CHECK_THROWS_WITH_AS(load_gltf(path, purple),
                       doctest::Contains("--variant \"purple\" is not a material variant of the "
                                         "file (it has: blue, green, also green)"),
                       SettingError);
}

TEST_CASE("KHR_materials_variants: the CLI's --variant and dacrt info") {
  TempDir dir("gltf-variants-cli");
  const std::string path = variants_file().write_gltf(dir / "variants.gltf");
  const Run info = run(dir, "info " + path);
  CHECK(info.code == 0);
  CHECK(info.out.find("variants   3 (render --variant NAME): blue, green, also green") !=
        std::string::npos);
  const std::string render =
      "render " + path + " --width 4 --height 4 --spp 1 --quiet -o " + (dir / "out.exr");
  CHECK(run(dir, render + " --variant green").code == 0);
  const Run wrong = run(dir, render + " --variant purple");
  CHECK(wrong.code == 2);
  CHECK(lines(wrong.err) == 1);
  CHECK(wrong.err.find("it has: blue, green, also green") != std::string::npos);
  CHECK(!fs::exists(dir / "out.exr.tmp"));
}

TEST_CASE("KHR_materials_variants: broken lists and mappings are schema errors") {
  TempDir dir("gltf-variants-schema");
  GltfWriter w = variants_file();
  w.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"][0]
       ["variants"] = {5};
  check_error(w.write_gltf(dir / "index.gltf"),
              {"/meshes/0/primitives/0/extensions/KHR_materials_variants/mappings/0/variants/0"});
  w = variants_file();
  w.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"][1]
       ["material"] = 9;
  check_error(w.write_gltf(dir / "material.gltf"),
              {"/meshes/0/primitives/0/extensions/KHR_materials_variants/mappings/1/material"});
  w = variants_file();
  w.doc["extensions"]["KHR_materials_variants"]["variants"][1].erase("name");
  check_error(w.write_gltf(dir / "name.gltf"),
              {"/extensions/KHR_materials_variants/variants/1", "name"});
}

TEST_CASE("KHR_materials_variants: a variant reads the images only it uses, .gltf and .glb alike") {
  TempDir dir("gltf-variants-images");
  const struct {
    Embed embed;
    const char* name;
  } cases[] = {{Embed::file, "file.gltf"},
               {Embed::data_uri, "data-uri.gltf"},
               {Embed::buffer_view, "view.glb"}};
  for (const auto& c : cases) {
    INFO(c.name);
    // The quad is red by its own material; variant "blue" maps it to material 1, textured by a
    // blue image that nothing else uses; variant "plain" maps nothing.
    GltfWriter w = quad_file({{"pbrMetallicRoughness", {{"baseColorFactor", {1, 0, 0, 1}}}}});
    add_texture(w, png8(1, 1, 4, {0, 0, 255, 255}), kNearest, c.embed, dir.path().string());
    w.add_material({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
    w.doc["extensionsUsed"] = {"KHR_materials_variants"};
    w.doc["extensions"]["KHR_materials_variants"]["variants"] = {{{"name", "blue"}},
                                                                 {{"name", "plain"}}};
    w.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"] = {
        {{"material", 1}, {"variants", {0}}}};
    const std::string path =
        c.embed == Embed::buffer_view ? w.write_glb(dir / c.name) : w.write_gltf(dir / c.name);
    auto colour = [&](const std::string& variant) {
      GltfOptions o;
      o.variant = variant;
      return quad_surface(load_gltf(path, o), 0.5f, 0.25f).brdf.base_color;
    };
    CHECK(near(colour(""), {1, 0, 0}));
    CHECK(near(colour("blue"), {0, 0, 1}));
    CHECK(near(colour("plain"), {1, 0, 0}));
    if (c.embed == Embed::file) {
      // The image file is read (and in the render's fingerprint) for the variant that uses it only.
      auto image_bytes = [&](const std::string& variant) {
        GltfOptions o;
        o.variant = variant;
        for (const FileRead& f : load_gltf(path, o).files)
          if (f.path.find("image0.png") != std::string::npos) return f.bytes.value_or(0);
        return uint64_t(0);
      };
      CHECK(image_bytes("") == 0);
      CHECK(image_bytes("blue") > 0);
    }
    // The CLI renders the variant.
    const Run r = run(dir, "render " + path + " --variant blue --width 4 --height 4 --spp 1 " +
                               "--integrator albedo --quiet -o " + (dir / "blue.exr"));
    INFO(r.err);
    CHECK(r.code == 0);
  }
}
