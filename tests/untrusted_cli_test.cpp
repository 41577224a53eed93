// Hostile and careless command lines: outputs that collide with each other or with inputs, inputs
// that are not regular files, prerequisites that would fail only after the render, sizes derived
// from a camera, file-size limits and full disks, a standard output that cannot be written. Each
// fails with one line naming what is wrong, exit 1 (2 for usage), writes nothing and leaves the
// inputs as they were.
#include <doctest/doctest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

#include "cli_scene.h"
#include "ocio_config.h"
#include "dacrt/util/memory.h"

using namespace dacrt::test;
namespace fs = std::filesystem;

TEST_CASE("untrusted cli: outputs that name the same file, or an input, are refused first") {
  TempDir dir("collide");
  const std::string scene = small_scene(dir);
  const std::string before = slurp(scene);
  const std::string render = "render " + scene + " --spp 1 --quiet ";
  const std::string out = dir / "out.exr";
  // -o and --stats, -o and --preview: the same file spelt the same or otherwise.
  check_refused(run(dir, render + "-o " + out + " --stats " + out), 1,
                {"--stats", "-o", "same file"});
  check_refused(run(dir, render + "-o " + out + " --preview " + out), 1, {"--preview", "-o"});
  fs::create_directory(dir.path() / "sub");
  check_refused(run(dir, render + "-o " + out + " --preview " + (dir / "./sub/../out.exr")), 1,
                {"--preview", "same file"});
  check_refused(run(dir, render + "--stats " + out + " --preview " + out), 1,
                {"--stats", "--preview"});
  // Through a symbolic link (dangling: out.exr does not exist yet), and a hard link.
  fs::create_symlink("out.exr", dir.path() / "link.exr");
  check_refused(run(dir, render + "-o " + out + " --stats " + (dir / "link.exr")), 1,
                {"link.exr", "same file"});
  fs::remove(dir.path() / "link.exr");
  // An output that is an input: the scene (by another path), the environment map.
  check_refused(run(dir, render + "-o " + scene), 2, {"-o", "'.gltf'"});  // (not an image's name)
  fs::create_symlink("s.gltf", dir.path() / "scene.exr");
  check_refused(run(dir, render + "-o " + (dir / "scene.exr")), 1,
                {"-o", "would overwrite the scene"});
  fs::remove(dir.path() / "scene.exr");
  check_refused(run(dir, render + "--stats " + (dir / "sub/../s.gltf")), 1, {"--stats", "scene"});
  fs::create_hard_link(scene, dir.path() / "hard.png");
  check_refused(run(dir, render + "--preview " + (dir / "hard.png")), 1, {"hard.png", "scene"});
  fs::remove(dir.path() / "hard.png");
  check_refused(run(dir, "bench " + scene + " --count 16 --repeat 1 --quiet --json " + scene), 1,
                {"--json", "would overwrite the scene"});
  // Several backends: each image gets its name, so one named twice would collide.
  check_refused(run(dir, render + "-o " + out + " --backend dacrt,dacrt"), 2, {"dacrt", "twice"});
  CHECK(slurp(scene) == before);
  fs::remove_all(dir.path() / "sub");
  check_no_outputs(dir);
  // Distinct files pass.
  Run ok = run(dir, render + "-o " + out + " --stats " + (dir / "out.json"));
  CHECK(ok.code == 0);
}

TEST_CASE("untrusted cli: no output may replace a file the scene reads") {
  TempDir dir("collide-external");
  GltfWriter w;
  w.add_triangles({{-1, -1, -3}, {1, -1, -3}, {0, 1, -3}});
  const std::string scene = dir / "ext.gltf", buffer = dir / "ext.bin";
  w.write_gltf(scene, false);  // the buffer in ext.bin beside it
  const std::string bytes = slurp(buffer);
  const std::string render = "render " + scene + " --spp 1 --quiet --width 4 --height 4 ";
  fs::create_hard_link(buffer, dir.path() / "ext.exr");
  check_refused(run(dir, render + "-o " + (dir / "ext.exr")), 1,
                {"-o", "ext.exr", "the scene's external file"});
  fs::remove(dir.path() / "ext.exr");
  check_refused(run(dir, render + "-o " + (dir / "o.exr") + " --stats " + (dir / "./ext.bin")), 1,
                {"--stats", "external file"});
  CHECK(slurp(buffer) == bytes);
  for (const auto& e : fs::directory_iterator(dir.path()))
    CHECK_MESSAGE((e.path().filename() == "ext.gltf" || e.path().filename() == "ext.bin"),
                  "left behind: " << e.path());
}

TEST_CASE("untrusted cli: the environment map as output, and outputs through links") {
  TempDir dir("collide-env");
  const std::string scene = small_scene(dir);
  const std::string env = dir / "sky.exr";
  REQUIRE(
      run(dir, "render " + scene + " --spp 1 --quiet -o " + env + " --width 8 --height 4").code ==
      0);
  const std::string sky = slurp(env);
  const std::string render = "render " + scene + " --spp 1 --quiet --environment " + env;
  check_refused(run(dir, render + " -o " + env), 1, {"-o", "environment map"});
  check_refused(run(dir, render + " -o " + (dir / "o.exr") + " --stats " + env), 1,
                {"--stats", "environment map"});
  CHECK(slurp(env) == sky);
  // A link as output: the file it points to is replaced, the link stays a link.
  fs::create_symlink("target.exr", dir.path() / "link.exr");
  REQUIRE(
      run(dir, "render " + scene + " --spp 1 --quiet --width 4 --height 4 -o " + (dir / "link.exr"))
          .code == 0);
  CHECK(fs::is_symlink(fs::symlink_status(dir.path() / "link.exr")));
  CHECK(fs::is_regular_file(dir.path() / "target.exr"));
}

TEST_CASE("untrusted cli: inputs and outputs that are not regular files") {
  TempDir dir("not-regular");
  const std::string scene = small_scene(dir);
  const std::string fifo = dir / "fifo.exr";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  const std::string render = "render " + scene + " --spp 1 --quiet -o " + (dir / "o.exr");
  // A FIFO as environment map or as $OCIO blocked the reader forever: refused (the timeout is
  // only there so that a regression fails instead of hanging the suite).
  check_refused(run(dir, render + " --environment " + fifo, "timeout 60"), 1,
                {"fifo.exr", "environment map", "FIFO"});
  check_refused(run(dir, render + " --preview " + (dir / "p.png"), "OCIO=" + fifo + " timeout 60"),
                1, {"fifo.exr", "OCIO", "FIFO"});
  check_refused(run(dir, "info " + fifo, "timeout 60"), 1, {"fifo.exr", "regular file"});
  fs::create_directory(dir.path() / "d.exr");
  check_refused(run(dir, render + " --environment " + (dir / "d.exr")), 1, {"d.exr", "directory"});
  // Outputs: renaming a new file over a FIFO (or, for root, over /dev/null) would replace it.
  check_refused(run(dir, "render " + scene + " --spp 1 --quiet -o " + fifo), 1,
                {"fifo.exr", "FIFO"});
  check_refused(run(dir, "render " + scene + " --spp 1 --quiet --stats " + fifo), 1, {"FIFO"});
  CHECK(fs::is_fifo(fifo));
  fs::create_symlink("/dev/null", dir.path() / "null.exr");
  check_refused(run(dir, "render " + scene + " --spp 1 --quiet -o " + (dir / "null.exr")), 1,
                {"/dev/null", "character device"});
  fs::remove(dir.path() / "null.exr");
  CHECK(fs::is_character_file("/dev/null"));
  fs::remove(fifo);
  fs::remove(dir.path() / "d.exr");
  check_no_outputs(dir);
}

TEST_CASE("untrusted cli: a broken $OCIO is an error before the render, not after") {
  TempDir dir("ocio");
  const std::string scene = small_scene(dir);
  write_text(dir / "bad.ocio", "ocio_profile_version: 2\nthis is: [not a config\n");
  // A million samples per pixel would take hours: the error must come first.
  const std::string render =
      "render " + scene + " --spp 1000000 -o " + (dir / "o.exr") + " --preview " + (dir / "o.png");
  for (const std::string& config : {dir / "bad.ocio", dir / "missing.ocio"}) {
    Run r = run(dir, render, "OCIO=" + config + " timeout 120");
    check_refused(r, 1, {config, "OCIO"});
    check_refused(run(dir, "views", "OCIO=" + config), 1, {config, "OCIO"});
  }
  fs::remove(dir.path() / "bad.ocio");
  check_no_outputs(dir);
  // Without a preview, $OCIO is not used.
  CHECK(run(dir, "render " + scene + " --spp 1 --quiet -o " + (dir / "o.exr"),
            "OCIO=" + (dir / "missing.ocio"))
            .code == 0);
}

TEST_CASE("untrusted cli: an unknown view is a usage error before the render, naming the valid ones") {
  TempDir dir("view");
  const std::string scene = small_scene(dir);
  const std::string render =
      "render " + scene + " --spp 1000000 -o " + (dir / "o.exr") + " --preview " + (dir / "o.png");
  // The caller's mistake, not the input's: exit 2, as every usage error.
  check_refused(run(dir, render + " --view Nope", "env -u OCIO timeout 120"), 2,
                {"'Nope'", "'sRGB'", "'ACES 1.0 SDR-video (sRGB)'"});
  // With $OCIO, the config's views are the valid ones, and the built-in names are not among them.
  TempDir config_dir("view-config");
  write_text(config_dir / "config.ocio", ocio_test_config);
  check_refused(
      run(dir, render + " --view sRGB", "OCIO=" + (config_dir / "config.ocio") + " timeout 120"), 2,
      {"'sRGB'", config_dir / "config.ocio", "'Test/Gamma2'", "'Other/Half'"});
  check_no_outputs(dir);
}

TEST_CASE("untrusted cli: sizes derived from a camera meet the limits of the flags") {
  TempDir dir("aspect");
  // aspectRatio 1e-7 with --width 8 asked for a height of 80 000 000 (the flags stop at 32 768).
  const std::string thin = small_scene(dir, 1e-7, "thin.gltf");
  check_refused(
      run(dir, "render " + thin + " --width 8 --quiet -o " + (dir / "o.exr")), 1,
      {"thin.gltf", "camera 0", "aspectRatio 1e-07 with --width 8", "height of ", "32768"});
  const std::string wide = small_scene(dir, 1e7, "wide.gltf");
  check_refused(run(dir, "render " + wide + " --height 8 --quiet -o " + (dir / "o.exr")), 1,
                {"wide.gltf", "--height 8", "width of "});
  // dacrt bench derives its primary resolution the same way.
  check_refused(run(dir, "bench " + thin + " --width 8 --rays primary --repeat 1 --quiet"), 1,
                {"thin.gltf", "aspectRatio 1e-07 with --width 8", "32768"});
  CHECK(run(dir, "bench " + thin + " --count 4096 --rays primary --repeat 1 --quiet").code == 0);
  // The default size keeps the longer side at 512, whatever the ratio.
  CHECK(run(dir, "render " + wide + " --spp 1 --quiet -o " + (dir / "o.exr")).code == 0);
  fs::remove(dir.path() / "o.exr");
  // Within the limit, given both: the ratio is not used.
  CHECK(run(dir, "render " + thin + " --width 8 --height 8 --spp 1 --quiet -o " + (dir / "o.exr"))
            .code == 0);
}

TEST_CASE("untrusted cli: a render that cannot fit in memory is refused before it starts") {
  TempDir dir("memory");
  const std::string scene = small_scene(dir);
  // 32768² pixels: a film of 36 GiB before anything else.
  if (dacrt::available_memory() > (uint64_t(64) << 30)) {
    MESSAGE("skipped: this machine has over 64 GiB available, a 32768² render could start");
    return;
  }
  Run r =
      run(dir,
          "render " + scene + " --width 32768 --height 32768 --spp 1 --quiet -o " + (dir / "o.exr"),
          "timeout 120");
  check_refused(r, 1, {"s.gltf", "32768 x 32768", "needs about", "GiB", "available"});
  check_no_outputs(dir);
}

TEST_CASE("untrusted cli: a small file that instances a mesh into more triangles than fit") {
#if defined(__SANITIZE_ADDRESS__)
  MESSAGE("skipped: AddressSanitizer cannot run under an address-space limit");
#else
  TempDir dir("instances");
  // 400 KB of file: a mesh of 100 000 triangles (u8 indices) under 100 nodes, 10 M triangles.
  GltfWriter w;
  std::vector<uint8_t> indices;
  for (int t = 0; t < 100000; ++t) indices.insert(indices.end(), {0, 1, 2});
  const int mesh = w.add_mesh(GltfWriter::primitive(w.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}),
                                                    {{"indices", w.add_indices(indices)}}));
  std::vector<int> nodes;
  for (int n = 0; n < 100; ++n)
    nodes.push_back(w.add_node({{"mesh", mesh}, {"translation", {n, 0, 0}}}));
  w.set_scene(nodes);
  const std::string scene = w.write_gltf(dir / "many.gltf");
  // Under a 1 GB address space (ulimit -v counts KiB), 10 M triangles cannot be held: refused with
  // what is too big, where they used to end in "out of memory while loading" (or the OOM killer).
  for (const std::string& command :
       {"info " + scene, "render " + scene + " --spp 1 --quiet -o " + (dir / "o.exr")})
    check_refused(run(dir, command, "ulimit -v 1000000;"), 1,
                  {"many.gltf", "mesh 0 primitive 0 brings the scene to", "triangles",
                   "of memory available"});
  check_no_outputs(dir);
  // Without the limit it loads.
  Run info = run(dir, "info " + scene);
  CHECK(info.code == 0);
  CHECK(info.out.find("triangles  10000000") != std::string::npos);
#endif
}

TEST_CASE("untrusted cli: a file-size limit is one error line and leaves no temporary file") {
  TempDir dir("fsize");
  const std::string scene = small_scene(dir);
  // ulimit -f counts 512-byte blocks (dash): 20 KiB, less than a 256² EXR.
  Run r = run(dir,
              "render " + scene + " --spp 1 --quiet --width 256 --height 256 -o " + (dir / "o.exr"),
              "ulimit -f 20;");
  check_refused(r, 1, {"o.exr", "File too large"});
  r = run(dir,
          "render " + scene + " --spp 1 --quiet --width 256 --height 256 -o " + (dir / "o.exr") +
              " --preview " + (dir / "o.png"),
          "ulimit -f 20;");
  check_refused(r, 1, {"File too large"});
  check_no_outputs(dir);
}

TEST_CASE("untrusted cli: output to a full standard output is an error") {
  TempDir dir("full");
  const std::string scene = small_scene(dir);
  check_refused(run(dir, "info " + scene, "", "/dev/full"), 1, {"standard output"});
  check_refused(run(dir, "--help", "", "/dev/full"), 1, {"standard output"});
  check_refused(run(dir, "render --help", "", "/dev/full"), 1, {"standard output"});
  check_refused(run(dir, "views", "", "/dev/full"), 1, {"standard output"});
  check_refused(run(dir, "views --help", "", "/dev/full"), 1, {"standard output"});
  check_refused(
      run(dir, "bench " + scene + " --count 64 --repeat 1 --rays primary --quiet", "", "/dev/full"),
      1, {"standard output"});
  // The comparison table of several backends goes to stdout too.
  Run r =
      run(dir,
          "render " + scene + " --spp 1 --quiet --width 8 --height 8 --backend dacrt,brute -o " +
              (dir / "o.exr"),
          "", "/dev/full");
  check_refused(r, 1, {"standard output"});
  CHECK(run(dir, "info " + scene).code == 0);
}

TEST_CASE("untrusted cli: triangles of zero area are dropped and counted by info and --stats") {
  TempDir dir("zero-area-cli");
  // One real triangle in front of the camera and 100 000 at one point behind it.
  GltfWriter w;
  std::vector<glm::vec3> p = {{-1, -1, -3}, {1, -1, -3}, {0, 1, -3}};
  p.resize(3 + 300000, glm::vec3(0, 0, -2));
  w.add_triangles(p);
  w.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.01}}}}};
  w.set_scene({0, w.add_node({{"camera", 0}})});
  const std::string scene = w.write_gltf(dir / "z.gltf");
  const Run info = run(dir, "info " + scene);
  REQUIRE_MESSAGE(info.code == 0, info.err);
  CHECK_MESSAGE(info.out.find("triangles  1 (100000 more of zero area dropped") != std::string::npos,
                info.out);
  const Run r = run(dir, "render " + scene + " --spp 1 --width 8 --height 8 --quiet -o " +
                             (dir / "z.exr") + " --stats " + (dir / "z.json"));
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const nlohmann::json stats = nlohmann::json::parse(slurp(dir / "z.json"));
  CHECK(stats.dump().find("\"degenerate_triangles\":100000") != std::string::npos);
  CHECK(stats.dump().find("\"triangles\":1,") != std::string::npos);
}

TEST_CASE("untrusted cli: a long --frames range of a missing scene fails at once") {
  // 100 000 frames name 100 000 outputs, each resolved once (they used to be compared in pairs:
  // minutes of file-system walks before the missing scene was said). `timeout` turns a hang into
  // a failure here; how fast it is, is the benchmark's business.
  TempDir dir("frames-missing");
  const Run r = run(dir, "render " + (dir / "missing.gltf") + " --frames 0:99999 -o " +
                             (dir / "f.exr") + " --preview " + (dir / "f.png"),
                    "timeout 60");
  check_refused(r, 1, {"missing.gltf", "does not exist"});
  // Outputs of a sequence that collide are still found (each frame's preview would be its EXR).
  const std::string scene = small_scene(dir);
  const Run same = run(dir, "render " + scene + " --frames 0:999 -o " + (dir / "a.exr") +
                                " --preview " + (dir / "a.exr"),
                       "timeout 60");
  check_refused(same, 1, {"is the same file as"});
  check_no_outputs(dir);
}
