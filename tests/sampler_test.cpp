// The samplers (integrators/sampler.h): the Sobol patterns are stratified, differ per pixel, seed
// and depth, keep their pairs apart, and make the error fall faster than the independent hash's
// spp^-1/2, measured on a render against a reference.
#include "dacrt/integrators/sampler.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "dacrt/render/render_job.h"
#include "test_geometry.h"

using namespace dacrt;
using namespace dacrt::test;

namespace {

constexpr Dimension pairs[][2] = {{pixel_x, pixel_y},
                                  {lens_u, lens_v},
                                  {light_u, light_v},
                                  {bsdf_u, bsdf_v},
                                  {environment_u, environment_v},
                                  {environment_pixel_u, environment_pixel_v}};
constexpr Dimension singles[] = {light_pick, bsdf_lobe, roulette, light_source};

}  // namespace

TEST_CASE("sampler: a pixel's first 2^k points hold one point in each elementary interval") {
  for (uint32_t pixel : {0u, 1u, 777u})
    for (uint32_t depth : {0u, 3u})
      for (uint32_t k = 0; k <= 8; ++k) {
        const uint32_t n = 1u << k;
        for (const auto& pair : pairs)
          for (uint32_t a = 0; a <= k; ++a) {  // intervals of 2^-a × 2^-(k−a)
            std::set<uint64_t> cells;
            for (uint32_t i = 0; i < n; ++i) {
              const float x = sobol_number(5, pixel, i, depth, pair[0]);
              const float y = sobol_number(5, pixel, i, depth, pair[1]);
              cells.insert(uint64_t(x * float(1u << a)) << 32 | uint64_t(y * float(1u << (k - a))));
            }
            INFO("pixel " << pixel << ", depth " << depth << ", dimension " << pair[0] << ", 2^"
                          << k << " points in intervals of 2^-" << a << " × 2^-" << k - a);
            CHECK(cells.size() == n);
          }
        for (Dimension dim : singles) {
          std::set<uint32_t> cells;
          for (uint32_t i = 0; i < n; ++i)
            cells.insert(uint32_t(sobol_number(5, pixel, i, depth, dim) * float(n)));
          CHECK(cells.size() == n);
        }
      }
}

TEST_CASE("sampler: different pixels, seeds and depths give different scrambles, all below 1") {
  auto first_points = [](uint64_t seed, uint32_t pixel, uint32_t depth, Dimension dim) {
    std::vector<float> v;
    for (uint32_t i = 0; i < 16; ++i) v.push_back(sobol_number(seed, pixel, i, depth, dim));
    return v;
  };
  for (Dimension dim : {pixel_x, light_pick, bsdf_v}) {
    const auto base = first_points(0, 0, 0, dim);
    CHECK(first_points(0, 1, 0, dim) != base);
    CHECK(first_points(1, 0, 0, dim) != base);
    CHECK(first_points(0, 0, 1, dim) != base);
  }
  for (SamplerKind kind : {SamplerKind::independent, SamplerKind::sobol})
    for (uint32_t i : {0u, 1u, 2u, 0x7fffffffu, 0xfffffffeu, 0xffffffffu})
      for (uint32_t pixel = 0; pixel < 64; ++pixel)
        for (uint32_t dim = 0; dim <= alpha; ++dim) {
          const float x = sample_number(kind, 9, pixel, i, 2, Dimension(dim));
          CHECK((x >= 0.f && x < 1.f));
        }
}

TEST_CASE("sampler: the index shuffle decorrelates the pairs") {
  // Without the shuffle point i of every pair would sit in the same half of [0, 1) in all pairs
  // (or the opposite half in all): the first coordinate's top bit is bit 0 of i, flipped per pair.
  // Shuffled, pairs agree on the half of a pixel's 16 points about half the time.
  int all_or_none = 0;
  for (uint32_t pixel = 0; pixel < 100; ++pixel) {
    int agree = 0;
    for (uint32_t i = 0; i < 16; ++i)
      agree += (sobol_number(0, pixel, i, 0, pixel_x) < 0.5f) ==
               (sobol_number(0, pixel, i, 0, bsdf_u) < 0.5f);
    all_or_none += agree == 0 || agree == 16;
  }
  CHECK(all_or_none <= 5);
}

TEST_CASE("sampler: a pixel's first 16 points are Owen-scrambled, each at its own place in its cell") {
  // A pixel's first 16 numbers of a dimension hold one in each sixteenth of [0, 1) whatever the
  // scramble; only a nested (Owen) scramble also draws each one's place inside its sixteenth by
  // its own hash. A plain XOR with the seed (a digital shift) keeps the stratification but puts
  // all 16 at the same place in their cells, a place shared by the 16: their sampled positions
  // move together and the noise rises. Each pixel's 16 places are distinct and, over 256 pixels,
  // uniform and nearly uncorrelated from one point to the next.
  std::vector<Dimension> dims(std::begin(singles), std::end(singles));
  for (const auto& pair : pairs) dims.insert(dims.end(), {pair[0], pair[1]});
  for (Dimension dim : dims)
    for (uint32_t depth : {0u, 5u}) {
      INFO("dimension " << dim << ", depth " << depth);
      int distinct = 0;
      double sum = 0.0, sum_sq = 0.0, lag = 0.0;
      constexpr int pixel_count = 256;
      for (uint32_t pixel = 0; pixel < pixel_count; ++pixel) {
        std::set<uint32_t> cells;
        std::set<float> places;
        std::vector<double> place(16);
        for (uint32_t i = 0; i < 16; ++i) {
          const float x = sobol_number(3, pixel, i, depth, dim);
          const float cell = std::floor(x * 16.f);
          cells.insert(uint32_t(cell));
          place[i] = double(x * 16.f - cell);  // exact: x has 24 bits
          places.insert(float(place[i]));
          sum += place[i], sum_sq += place[i] * place[i];
        }
        CHECK(cells.size() == 16);
        distinct += places.size() == 16;
        for (uint32_t i = 0; i + 1 < 16; ++i) lag += (place[i] - 0.5) * (place[i + 1] - 0.5);
      }
      const double n = 16.0 * pixel_count, mean = sum / n, var = sum_sq / n - mean * mean;
      CHECK(distinct == pixel_count);
      // Uniform on [0, 1): mean 1/2 ± 4 standard errors (√(1/12 / 4096) = 0.0045), variance 1/12.
      CHECK(std::abs(mean - 0.5) < 0.018);
      CHECK(var == doctest::Approx(1.0 / 12.0).epsilon(0.08));
      // The correlation of neighbours' places: 1 under a plain XOR. The Laine–Karras hash is not
      // a perfect Owen scramble: it leaves about 0.1 (0.07–0.14 over these dimensions), where an
      // ideal one gives 0 ± 0.016.
      CHECK(std::abs(lag / (15.0 * pixel_count) / var) < 0.2);
    }
}

namespace {

// A Lambert plane seen from above (orthographic, 16 × 16 pixels), lit by a square emitter and
// shaded by a strip between them: soft shadow edges, a smooth falloff, one scattering event.
Scene penumbra_scene() {
  Scene scene;
  const glm::vec3 a(-2, -2, 0), b(2, -2, 0), c(2, 2, 0), d(-2, 2, 0);
  scene.geometry.add(a, b, c, 0);
  scene.geometry.add(a, c, d, 0);
  const glm::vec3 la(-0.5f, -0.5f, 2), lb(0.5f, -0.5f, 2), lc(0.5f, 0.5f, 2), ld(-0.5f, 0.5f, 2);
  scene.geometry.add(la, lc, lb, 1);  // facing −z
  scene.geometry.add(la, ld, lc, 1);
  const glm::vec3 oa(-0.1f, -3, 1), ob(0.1f, -3, 1), oc(0.1f, 3, 1), od(-0.1f, 3, 1);
  scene.geometry.add(oa, ob, oc, 0);
  scene.geometry.add(oa, oc, od, 0);
  Material light = Material::lambert(glm::vec3(0.f));
  light.emission = glm::vec3(4.f);
  scene.materials = {Material::lambert(glm::vec3(0.5f)), light};
  Camera cam = looking_at(glm::vec3(0, 0, 0.9f), glm::vec3(0), 1.f);
  cam.orthographic = true;
  cam.ymag = 1.f;
  scene.cameras = {cam};
  return scene;
}

std::vector<double> render_means(const Scene& scene, Backend& backend, SamplerKind kind,
                                 uint64_t seed, int spp) {
  RenderSettings s;
  s.width = s.height = 16, s.spp = spp, s.seed = seed, s.sampler = kind, s.integrator = "direct";
  RenderJob job(scene, backend, s);
  Film film = job.film();
  Progress quiet("test", 1, false);
  job.run(film, 0, uint32_t(spp), quiet);
  std::vector<double> means(film.pixels());
  for (size_t p = 0; p < film.pixels(); ++p) means[p] = film.mean_and_error(p).x;
  return means;
}

// The least-squares slope of y against x, and its standard error from the y's own errors.
struct Slope {
  double slope, error;
};
Slope fit(const std::vector<double>& x, const std::vector<double>& y,
          const std::vector<double>& y_error) {
  double mx = 0.0, my = 0.0;
  for (size_t i = 0; i < x.size(); ++i) mx += x[i] / x.size(), my += y[i] / y.size();
  double sxx = 0.0, sxy = 0.0;
  for (size_t i = 0; i < x.size(); ++i) sxx += (x[i] - mx) * (x[i] - mx);
  for (size_t i = 0; i < x.size(); ++i) sxy += (x[i] - mx) * (y[i] - my);
  double var = 0.0;
  for (size_t i = 0; i < x.size(); ++i) var += std::pow((x[i] - mx) / sxx * y_error[i], 2);
  return {sxy / sxx, std::sqrt(var)};
}

}  // namespace

constexpr int reference_spp = 2048;

TEST_CASE("sampler: RMSE falls as spp^-1/2 with independent numbers, faster with sobol") {
  // RMSE against a sobol reference of 2048 spp, at 1, 2, … 64 spp, each averaged over 8 seeds
  // (256 pixels × 8 = 2048 squared errors). The standard error of each log RMSE comes from the
  // spread of those squared errors (relative error of their mean, halved), and the slope's from
  // those through the least-squares weights; 4 of them bound the noise. The reference's own error
  // adds at most MSE(1 spp of independent) / 2048 to every MSE (sobol converges faster than
  // that), which bends the fitted slope by the `bias` below, added to the tolerance.
  const Scene scene = penumbra_scene();
  auto backend = Backend::create("dacrt", scene.geometry);
  const std::vector<double> reference =
      render_means(scene, *backend, SamplerKind::sobol, 1000, reference_spp);
  std::vector<double> log_spp;
  for (int spp = 1; spp <= 64; spp *= 2) log_spp.push_back(std::log(double(spp)));
  auto log_rmse = [&](SamplerKind kind, std::vector<double>& error, double& mse1) {
    std::vector<double> y;
    error.clear();
    for (int spp = 1; spp <= 64; spp *= 2) {
      double sum = 0.0, sum2 = 0.0;
      size_t n = 0;
      for (uint64_t seed = 1; seed <= 8; ++seed) {
        const std::vector<double> m = render_means(scene, *backend, kind, seed, spp);
        for (size_t p = 0; p < m.size(); ++p) {
          const double e2 = (m[p] - reference[p]) * (m[p] - reference[p]);
          sum += e2, sum2 += e2 * e2, ++n;
        }
      }
      const double mse = sum / n, sd = std::sqrt(std::max(0.0, sum2 / n - mse * mse));
      if (spp == 1) mse1 = mse;
      y.push_back(0.5 * std::log(mse));
      error.push_back(0.5 * sd / (mse * std::sqrt(double(n))));
    }
    return y;
  };
  std::vector<double> independent_error, sobol_error;
  double mse1 = 0.0, sobol_mse1 = 0.0;
  const Slope independent =
      fit(log_spp, log_rmse(SamplerKind::independent, independent_error, mse1), independent_error);
  const Slope sobol =
      fit(log_spp, log_rmse(SamplerKind::sobol, sobol_error, sobol_mse1), sobol_error);
  // The slope of 0.5 log(mse1 / spp + mse1 / reference_spp) minus −0.5: how far the reference
  // alone moves a true −0.5.
  std::vector<double> bent;
  for (double x : log_spp) bent.push_back(0.5 * std::log(std::exp(-x) + 1.0 / reference_spp));
  const double bias = fit(log_spp, bent, std::vector<double>(bent.size(), 0.0)).slope + 0.5;
  const double tolerance = 4.0 * independent.error + bias;
  INFO("independent: slope " << independent.slope << " ± " << independent.error << " (bias " << bias
                             << "), sobol: " << sobol.slope << " ± " << sobol.error);
  CHECK(std::abs(independent.slope + 0.5) <= tolerance);
  CHECK(sobol.slope <= -0.5 - 4.0 * sobol.error);
}

TEST_CASE("sampler: a pair drawn together is the two numbers drawn one by one") {
  for (SamplerKind kind : {SamplerKind::independent, SamplerKind::sobol})
    for (const auto& pair : pairs)
      for (uint32_t pixel : {0u, 7u, 123456u})
        for (uint32_t i : {0u, 1u, 5u, 1000u, 0xffffffffu})
          for (uint32_t depth : {0u, 3u, 63u}) {
            const auto both = sample_pair(kind, 11, pixel, i, depth, pair[0]);
            CHECK(both[0] == sample_number(kind, 11, pixel, i, depth, pair[0]));
            CHECK(both[1] == sample_number(kind, 11, pixel, i, depth, pair[1]));
          }
}

TEST_CASE("sampler: seed 0's pixel 0 is scrambled like any other") {
  // A pattern whose scramble seeds are all zero is the bare Sobol sequence: point 0 at (0, 0)
  // in every pair and every depth, the corner of pixel 0, in every render with seed 0.
  int zeros = 0;
  for (const auto& pair : pairs)
    for (uint32_t depth = 0; depth < 4; ++depth) {
      const auto p = sobol_pair(0, 0, 0, depth, pair[0]);
      zeros += p[0] == 0.f || p[1] == 0.f;
    }
  CHECK(zeros == 0);
}

TEST_CASE("sampler: sixteen vertices drawn at once get the numbers drawn one by one, bit for bit") {
  // With AVX-512 or AVX2 the Sobol lanes are vector code (the one this CPU runs is checked); with
  // neither this checks the scalar loop.
  std::vector<Dimension> dims;
  for (uint32_t d = 0; d < dimension_count; ++d)
    if (!(d > 0 && dimension_slots[d - 1].pair && dimension_slots[d - 1].component == 0))
      dims.push_back(Dimension(d));  // singles and the first of each pair
  uint64_t state = 0x1234;
  auto next = [&] { return uint32_t((state = mix64(state + 1)) >> 16); };
  for (SamplerKind kind : {SamplerKind::independent, SamplerKind::sobol})
    for (uint64_t seed : {0ull, 9ull})
      for (size_t lanes : {size_t(1), size_t(7), size_t(16), size_t(37)}) {
        const Sampler sampler(kind, seed);
        std::vector<uint32_t> pixel(lanes), index(lanes), depth(lanes);
        for (size_t k = 0; k < lanes; ++k) {
          pixel[k] = k % 3 == 0 ? 0u : next();
          index[k] = k % 4 == 1 ? 0xffffffffu : next() >> (k % 20);
          depth[k] = k % 5 == 2 ? (1u << 24) + 3u : next() % 70;  // depth is taken mod 2^24
        }
        std::vector<VertexNumbers> out(lanes);
        sampler.numbers(pixel.data(), index.data(), depth.data(), lanes, dims, out.data());
        int differ = 0;
        for (size_t k = 0; k < lanes; ++k)
          for (uint32_t d = 0; d < dimension_count; ++d)
            differ += out[k][d] != sampler.number(pixel[k], index[k], depth[k], Dimension(d));
        INFO("sampler " << sampler_name(kind) << ", seed " << seed << ", " << lanes << " lanes");
        CHECK(differ == 0);
      }
}

TEST_CASE("sampler: Sobol's second dimension by shifts and XORs is its direction numbers' XOR") {
  // The reference: direction number v_j (v_0 = 2^31, v_j = v_(j-1) ^ v_(j-1) >> 1) for each set
  // bit j of the index, XORed, then the bits reversed. Both are linear over GF(2), so agreeing on
  // the 32 single bits is agreeing everywhere; random indices and the edges are checked as well.
  uint32_t v[32];
  v[0] = 1u << 31;
  for (int j = 1; j < 32; ++j) v[j] = v[j - 1] ^ v[j - 1] >> 1;
  auto reference = [&](uint32_t s) {
    uint32_t x = 0;
    for (int j = 0; j < 32; ++j)
      if (s >> j & 1) x ^= v[j];
    uint32_t reversed = 0;
    for (int i = 0; i < 32; ++i) reversed |= (x >> i & 1) << (31 - i);
    return reversed;
  };
  std::vector<uint32_t> indices = {0u,          0xffffffffu, 0x80000000u,
                                   0x7fffffffu, 0x55555555u, 0xaaaaaaaau};
  for (int j = 0; j < 32; ++j) indices.push_back(1u << j);
  for (uint32_t s = 0; s < 4096; ++s) indices.push_back(s);
  uint64_t state = 51;
  for (int k = 0; k < 100000; ++k) indices.push_back(uint32_t((state = mix64(state + 1)) >> 7));
  int differ = 0;
  for (uint32_t s : indices) differ += sobol_dimension1_reversed(s) != reference(s);
  CHECK(differ == 0);
}

TEST_CASE("sampler: thousands of random vertices drawn at once get the numbers drawn one by one") {
  // The vector code's every lane count up to two registers' worth, and a long run, over random
  // pixels, indices (all 32 bits) and depths.
  std::vector<Dimension> dims;
  for (uint32_t d = 0; d < dimension_count; ++d)
    if (!(d > 0 && dimension_slots[d - 1].pair && dimension_slots[d - 1].component == 0))
      dims.push_back(Dimension(d));
  uint64_t state = 0x51;
  auto next = [&] { return uint32_t((state = mix64(state + 1)) >> 13); };
  std::vector<size_t> counts;
  for (size_t lanes = 1; lanes <= 2 * sampler_lanes + 1; ++lanes) counts.push_back(lanes);
  counts.push_back(4099);
  int differ = 0;
  for (uint64_t seed : {3ull, 0xfedcba9876543210ull}) {
    const Sampler sampler(SamplerKind::sobol, seed);
    for (size_t lanes : counts) {
      std::vector<uint32_t> pixel(lanes), index(lanes), depth(lanes);
      for (size_t k = 0; k < lanes; ++k) pixel[k] = next(), index[k] = next(), depth[k] = next();
      std::vector<VertexNumbers> out(lanes);
      sampler.numbers(pixel.data(), index.data(), depth.data(), lanes, dims, out.data());
      for (size_t k = 0; k < lanes; ++k)
        for (uint32_t d = 0; d < dimension_count; ++d)
          differ += out[k][d] != sampler.number(pixel[k], index[k], depth[k], Dimension(d));
    }
  }
  CHECK(differ == 0);
}
