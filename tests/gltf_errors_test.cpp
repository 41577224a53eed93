// The glTF loader on malformed input (io/gltf): files that cannot be read or parsed, damaged GLB
// containers, broken accessors and bufferViews, positions that are not finite, bad nodes, meshes,
// materials, cameras and lights. Each must give one dacrt::Error line naming the file and the
// element at fault.
#include <doctest/doctest.h>
#include <sys/stat.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "dacrt/io/gltf.h"
#include "tests/captured_stderr.h"
#include "tests/gltf_check.h"
#include "tests/gltf_triangle.h"
#include "tests/gltf_writer.h"

using dacrt::test::check_error;
using dacrt::test::GltfWriter;
using dacrt::test::kTriangle;
using dacrt::test::TempDir;
using dacrt::test::triangle_file;
using nlohmann::json;

TEST_CASE("gltf errors: files that cannot be read or parsed") {
  TempDir dir("bad-files");
  check_error(dir / "missing.gltf", {"file"});
  check_error(dir.path().string(), {"file"});
  dacrt::test::write_text(dir / "empty.gltf", "");
  check_error(dir / "empty.gltf", {"empty"});
  dacrt::test::write_text(dir / "broken.gltf",
                          "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [\n{ ");
  check_error(dir / "broken.gltf", {"JSON"});
  dacrt::test::write_text(
      dir / "deep.gltf", "{\"asset\":{\"version\":\"2.0\"},\"extras\":" + std::string(100000, '[') +
                             std::string(100000, ']') + "}");
  check_error(dir / "deep.gltf", {"JSON"});
  dacrt::test::write_text(dir / "text.glb", "{\"asset\":{\"version\":\"2.0\"}}");
  check_error(dir / "text.glb", {"GLB"});

  GltfWriter w = triangle_file();
  std::string path = w.write_gltf(dir / "side.gltf", /*embed=*/false);
  std::filesystem::remove(dir / "side.bin");
  check_error(path, {"buffer 0", "side.bin"});
  // A FIFO would block a reader forever: it must be refused like a missing file.
  REQUIRE(mkfifo((dir / "fifo.bin").c_str(), 0600) == 0);
  std::filesystem::rename(dir / "fifo.bin", dir / "side.bin");
  check_error(path, {"buffer 0", "side.bin"});
  w.doc["asset"].erase("version");
  check_error(w.write_gltf(dir / "noversion.gltf"), {"asset"});

  // An external image that is a FIFO is refused too, and the loader does not wait on it.
  GltfWriter textured;
  const std::vector<glm::vec2> uv = {{0, 0}, {1, 0}, {0, 1}};
  const int uv_accessor =
      textured.add_accessor(textured.add_view(uv.data(), sizeof(glm::vec2) * uv.size()),
                            dacrt::test::kFloat, uv.size(), "VEC2");
  const int material =
      textured.add_material({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  textured.add_triangles(kTriangle, {{"material", material}});
  textured.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = uv_accessor;
  textured.doc["textures"] = {{{"source", 0}}};
  textured.doc["images"] = {{{"uri", "fifo.png"}}};
  REQUIRE(mkfifo((dir / "fifo.png").c_str(), 0600) == 0);
  check_error(textured.write_gltf(dir / "fifo-image.gltf"), {"image 0", "fifo.png"});
}

TEST_CASE("gltf errors: damaged GLB containers") {
  TempDir dir("bad-glb");
  GltfWriter w = triangle_file();
  std::string path = w.write_glb(dir / "ok.glb");
  std::vector<unsigned char> glb(std::filesystem::file_size(path));
  std::ifstream(path, std::ios::binary)
      .read(reinterpret_cast<char*>(glb.data()), std::streamsize(glb.size()));
  auto write = [&](const char* name, std::vector<unsigned char> bytes) {
    dacrt::test::write_bytes(dir / name, bytes.data(), bytes.size());
    return dir / name;
  };
  check_error(write("short.glb", {glb.begin(), glb.begin() + 16}), {"GLB"});
  check_error(write("cut.glb", {glb.begin(), glb.end() - 8}), {"GLB"});
  // The BIN chunk says it is 8 bytes longer than what is left (tinygltf 2.7 would read past it).
  std::vector<unsigned char> longer = glb;
  uint32_t json_size = longer[12] | longer[13] << 8;
  longer[20 + json_size] += 8;
  check_error(write("bin-overrun.glb", longer), {"BIN chunk"});
  std::vector<unsigned char> v1 = glb;
  v1[4] = 1;
  check_error(write("v1.glb", v1), {"version"});
}

TEST_CASE("gltf errors: accessors and bufferViews") {
  TempDir dir("bad-accessors");
  {
    GltfWriter w = triangle_file();
    w.doc["accessors"][0]["count"] = 4;
    check_error(w.write_gltf(dir / "overrun.gltf"),
                {"accessor 0", "POSITION", "overruns bufferView 0"});
    w.doc["accessors"][0]["count"] = 4000000000u;  // absurd: must fail before allocating
    check_error(w.write_gltf(dir / "huge.gltf"), {"accessor 0", "overruns"});
    w.doc["accessors"][0].erase("bufferView");
    check_error(w.write_gltf(dir / "huge-zeros.gltf"), {"accessor 0", "bytes"});
  }
  {
    GltfWriter w = triangle_file();
    w.doc["accessors"][0]["byteOffset"] = 4;
    check_error(w.write_gltf(dir / "offset.gltf"), {"accessor 0", "overruns"});
  }
  {
    GltfWriter w = triangle_file();
    w.doc["bufferViews"][0]["byteLength"] = 1000;
    check_error(w.write_gltf(dir / "view.gltf"), {"bufferView 0", "overruns buffer 0"});
    w.doc["bufferViews"][0]["buffer"] = 3;
    check_error(w.write_gltf(dir / "nobuffer.gltf"), {"/bufferViews/0/buffer", "3"});
  }
  {
    GltfWriter w = triangle_file();
    w.doc["accessors"][0]["bufferView"] = 9;
    check_error(w.write_gltf(dir / "noview.gltf"), {"/accessors/0/bufferView", "9"});
    w.doc["accessors"][0]["bufferView"] = 0;
    w.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 5;
    check_error(w.write_gltf(dir / "noaccessor.gltf"),
                {"/meshes/0/primitives/0/attributes/POSITION", "5"});
  }
  {
    GltfWriter w = triangle_file();
    w.doc["accessors"][0]["componentType"] = dacrt::test::kUnsignedShort;
    w.doc["accessors"][0]["count"] = 1;
    check_error(w.write_gltf(dir / "type.gltf"), {"accessor 0", "FLOAT VEC3"});
  }
  {
    GltfWriter w = triangle_file();
    w.doc["bufferViews"][0]["byteStride"] = 8;
    check_error(w.write_gltf(dir / "stride.gltf"), {"accessor 0", "byteStride"});
  }
  {
    GltfWriter w;
    w.add_triangles(kTriangle, {{"indices", w.add_indices(std::vector<uint16_t>{0, 1, 3})}});
    check_error(w.write_gltf(dir / "index.gltf"),
                {"indices of mesh 0 primitive 0", "index 3", "vertex count 3"});
  }
  {
    GltfWriter w;
    w.add_triangles(kTriangle);
    std::vector<uint16_t> indices = {7};
    std::vector<glm::vec3> values = {{5, 5, 5}};
    json sparse = {{"count", 1},
                   {"indices",
                    {{"bufferView", w.add_view(indices.data(), 2)},
                     {"componentType", dacrt::test::kUnsignedShort}}},
                   {"values", {{"bufferView", w.add_view(values.data(), 12)}}}};
    w.doc["accessors"][0]["sparse"] = sparse;
    check_error(w.write_gltf(dir / "sparse-index.gltf"), {"accessor 0", "sparse index 7"});
    w.doc["accessors"][0]["sparse"]["count"] = 2;
    check_error(w.write_gltf(dir / "sparse-overrun.gltf"), {"accessor 0", "sparse", "overruns"});
  }
}

TEST_CASE("gltf errors: positions that are not finite") {
  TempDir dir("bad-positions");
  for (float bad :
       {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    GltfWriter w;
    w.add_triangles({{0, 0, 0}, {1, bad, 0}, {0, 1, 0}});
    w.doc["accessors"][0].erase("min");  // JSON has no NaN or inf: they would be null
    w.doc["accessors"][0].erase("max");
    check_error(w.write_gltf(dir / (std::isnan(bad) ? "nan.gltf" : "inf.gltf")),
                {"POSITION", "vertex 1", "not finite"});
  }
  GltfWriter w;
  w.add_triangles({{0, 0, 0}, {1e30f, 0, 0}, {0, 1, 0}});
  w.doc["nodes"][0]["scale"] = {1e30, 1, 1};  // finite in the file, infinite in the world
  check_error(w.write_gltf(dir / "overflow.gltf"), {"node 0", "vertex 1", "non-finite"});
}

TEST_CASE("gltf errors: nodes, meshes, materials and cameras") {
  TempDir dir("bad-nodes");
  auto broken = [&](const char* name, auto&& edit, std::initializer_list<std::string> words) {
    GltfWriter w = triangle_file();
    edit(w.doc);
    check_error(w.write_gltf(dir / name), words);
  };
  broken("child.gltf", [](json& d) { d["nodes"][0]["children"] = {4}; },
         {"/nodes/0/children/0", "4 is not an index"});
  broken("root.gltf", [](json& d) { d["scenes"][0]["nodes"] = {-1}; },
         {"/scenes/0/nodes/0", "-1 is not an index"});
  broken("self.gltf", [](json& d) { d["nodes"][0]["children"] = {0}; }, {"node 0", "cycle"});
  broken("cycle.gltf",
         [](json& d) {
           d["nodes"][0]["children"] = {1};
           d["nodes"][1] = {{"children", {2}}};
           d["nodes"][2] = {{"children", {0}}};
         },
         {"node 0", "cycle"});
  broken("parents.gltf",
         [](json& d) {
           d["nodes"][1] = {{"children", {0}}};
           d["scenes"][0]["nodes"] = {0, 1};
         },
         {"/scenes/0/nodes/0", "node 0 is not a root node"});
  broken("mesh.gltf", [](json& d) { d["nodes"][0]["mesh"] = 3; }, {"/nodes/0/mesh", "3"});
  broken("material.gltf", [](json& d) { d["meshes"][0]["primitives"][0]["material"] = 2; },
         {"/meshes/0/primitives/0/material", "2"});
  broken("camera.gltf", [](json& d) { d["nodes"][0]["camera"] = 0; },
         {"/nodes/0/camera", "no cameras"});
  broken("matrix.gltf",
         [](json& d) { d["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0}; },
         {"/nodes/0/matrix", "16 numbers"});
  broken("rotation.gltf",
         [](json& d) {
           d["nodes"][0]["rotation"] = {0, 0, 0, 0};
         },
         {"node 0", "rotation"});
  // Not a unit quaternion (ROTATION_NON_UNIT): which rotation is meant is unknown. Within 1 % of
  // unit length (files round theirs), it is normalised.
  broken("rotation-long.gltf", [](json& d) { d["nodes"][0]["rotation"] = {1, 1, 1, 1}; },
         {"node 0", "not a unit quaternion", "length is 2"});
  {
    GltfWriter w = triangle_file();
    w.doc["nodes"][0]["rotation"] = {0, 0, 0, 0.995};
    CHECK(dacrt::load_gltf(w.write_gltf(dir / "rotation-rounded.gltf")).geometry.size() == 1);
  }
  broken(
      "yfov.gltf",
      [](json& d) {
        d["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 4}, {"znear", 0.1}}}}};
        d["nodes"][0]["camera"] = 0;
      },
      {"camera 0", "yfov"});
  broken("strength.gltf",
         [](json& d) {
           d["materials"] = {
               {{"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", -1}}}}}}};
         },
         {"/materials/0/extensions/KHR_materials_emissive_strength/emissiveStrength"});
  broken("ior.gltf",
         [](json& d) {
           d["materials"] = {{{"extensions", {{"KHR_materials_ior", {{"ior", 0.5}}}}}}};
         },
         {"/materials/0/extensions/KHR_materials_ior/ior"});
  broken("ior-type.gltf",
         [](json& d) {
           d["materials"] = {{{"extensions", {{"KHR_materials_ior", {{"ior", "glass"}}}}}}};
         },
         {"/materials/0/extensions/KHR_materials_ior/ior"});
  broken("specular-color.gltf",
         [](json& d) {
           d["materials"] = {
               {{"extensions", {{"KHR_materials_specular", {{"specularColorFactor", {1, 1}}}}}}}};
         },
         {"/materials/0/extensions/KHR_materials_specular/specularColorFactor"});
  broken(
      "specular-negative.gltf",
      [](json& d) {
        d["materials"] = {
            {{"extensions", {{"KHR_materials_specular", {{"specularColorFactor", {1, -1, 1}}}}}}}};
      },
      {"/materials/0/extensions/KHR_materials_specular/specularColorFactor/1"});
  auto with_light = [](json light) {
    return [light](json& d) {
      d["extensions"]["KHR_lights_punctual"]["lights"] = {light};
      d["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 0;
    };
  };
  {
    // A type the extension does not define (the validator only warns): skipped, with a warning.
    GltfWriter w = triangle_file();
    with_light({{"type", "area"}})(w.doc);
    dacrt::test::CapturedStderr err;
    const dacrt::Scene scene = dacrt::load_gltf(w.write_gltf(dir / "light-type.gltf"));
    const std::string text = err.text();
    CHECK(scene.lights.empty());
    CHECK(scene.ignored.unknown_lights == 1);
    CHECK(text.find("1 lights of a type KHR_lights_punctual does not define (skipped)") !=
          std::string::npos);
    with_light({{"type", "point"}})(w.doc);
    CHECK(dacrt::load_gltf(w.write_gltf(dir / "light-point.gltf")).lights.size() == 1);
  }
  broken(
      "light-cone.gltf",
      with_light({{"type", "spot"}, {"spot", {{"innerConeAngle", 0.6}, {"outerConeAngle", 0.5}}}}),
      {"/extensions/KHR_lights_punctual/lights/0/spot/innerConeAngle"});
  broken("light-intensity.gltf", with_light({{"type", "point"}, {"intensity", -1}}),
         {"/extensions/KHR_lights_punctual/lights/0/intensity"});
  broken("light-color.gltf", with_light({{"type", "point"}, {"color", {1, 1}}}),
         {"/extensions/KHR_lights_punctual/lights/0/color"});
  broken("light-index.gltf",
         [](json& d) { d["nodes"][0]["extensions"]["KHR_lights_punctual"]["light"] = 4; },
         {"/nodes/0/extensions/KHR_lights_punctual/light", "4"});
  broken(
      "instances.gltf",
      [](json& d) {
        d["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"] = {{"attributes", json::object()}};
      },
      {"/nodes/0/extensions/EXT_mesh_gpu_instancing/attributes"});
  broken("draco.gltf", [](json& d) { d["extensionsRequired"] = {"KHR_draco_mesh_compression"}; },
         {"KHR_draco_mesh_compression"});
}
