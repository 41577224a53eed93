// direct: direct lighting only. At the first surface each camera ray meets, one next-event
// sample (an emissive triangle or punctual light picked by power, or the environment map) and
// one BSDF sample, combined by multiple importance sampling; emitters seen directly add their
// emission. Light that has scattered more than once is not computed. It is the path tracer with
// one scattering event, so it equals `path --max-depth 1` sample for sample (same seeds, same
// estimator): a fast preview of the lighting and a reference for light-sampling tests.
#include "dacrt/integrators/path.h"

namespace dacrt {
namespace {

const Integrator::Registration registration{
    "direct",
    [](const Scene& scene, const Shot& shot, Backend& backend, const RenderSettings& settings) {
      RenderSettings direct = settings;
      direct.max_depth = 1;
      return std::make_unique<PathTracer>(scene, shot, backend, direct);
    }};

}  // namespace
}  // namespace dacrt
