// A host program of the installed package: renders a scene as `dacrt render` does and checks
// that its colour channels are, bit for bit, those of the CLI's EXR of the same render.
//   consumer SCENE CLI.exr WIDTH HEIGHT SPP SEED
#include <dacrt/io/exr.h>
#include <dacrt/io/gltf.h>
#include <dacrt/render/render_job.h>
#include <dacrt/tracer/backend.h>
#include <dacrt/util/error.h>
#include <dacrt/util/progress.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#define HOST_INCLUDES_ITS_OWN
#include "util/error.h"  // the host's own, included last: dacrt's headers never reach it

static_assert(HOST_UTIL_ERROR_H == 1, "the host's util/error.h");

int main(int argc, char** argv) {
  if (argc != 7) {
    std::fprintf(stderr, "usage: consumer SCENE CLI.exr WIDTH HEIGHT SPP SEED\n");
    return 2;
  }
  try {
    const dacrt::Scene scene = dacrt::load_gltf(argv[1]);
    dacrt::RenderSettings s;
    s.width = std::atoi(argv[3]), s.height = std::atoi(argv[4]);
    s.spp = std::atoi(argv[5]), s.seed = uint32_t(std::strtoul(argv[6], nullptr, 10));
    const auto backend = dacrt::Backend::create("dacrt", scene.geometry);
    dacrt::RenderJob job(scene, *backend, s);
    dacrt::Film film = job.film();
    dacrt::Progress quiet("consumer", 1, false);
    job.run(film, 0, uint32_t(s.spp), quiet);

    const dacrt::ExrFile cli = dacrt::read_exr_file(argv[2]);
    size_t compared = 0;
    for (const dacrt::Channel& mine : film.channels()) {
      const dacrt::Channel* theirs = cli.find(mine.name);
      if (!theirs || theirs->values.size() != mine.values.size()) {
        std::fprintf(stderr, "consumer: channel %s missing or of another size\n", mine.name.c_str());
        return 1;
      }
      if (std::memcmp(theirs->values.data(), mine.values.data(), 4 * mine.values.size()) != 0) {
        std::fprintf(stderr, "consumer: channel %s differs from the CLI's\n", mine.name.c_str());
        return 1;
      }
      ++compared;
    }
    std::printf("consumer: %zu channels of %zu pixels the same as the CLI's\n", compared,
                film.pixels());
    return compared >= 3 ? 0 : 1;
  } catch (const dacrt::Error& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  } catch (const host::Error&) {
    return 1;
  }
}
