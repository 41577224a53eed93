// KHR_materials_iridescence: the thin-film Fresnel (materials/iridescence.h) against a direct
// computation, wavelength by wavelength, of the film's Airy reflectance integrated with the CIE
// 1931 matching functions; its physical limits (a film of the outside's IOR or of thickness 0 is
// the bare base, a quarter-wave film cancels reflection); F in [0, 1]. And the glTF BRDF with a
// film: sampling follows the pdf (χ²), weights are eval · cos / pdf, eval is reciprocal, the
// white furnace returns at most what it receives, the lobes' Fresnel is mix(F, F_film, factor),
// and a factor or a thickness of 0 leaves today's BRDF bit for bit.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <sstream>
#include <vector>

#include "brdf_check.h"
#include "dacrt/materials/ggx.h"
#include "dacrt/materials/gltf_brdf.h"
#include "dacrt/materials/iridescence.h"
#include "dacrt/materials/sampling.h"
#include "dacrt/util/random.h"

using namespace dacrt;
using dacrt::test::direction;

namespace {

// Fresnel's unpolarised reflectance from IOR 1 into IOR n (relative) at cos_i (1 at grazing).
double fresnel(double cos_i, double n) {
  const double sin2_t = (1.0 - cos_i * cos_i) / (n * n);
  if (!(sin2_t < 1.0)) return 1.0;
  const double cos_t = std::sqrt(1.0 - sin2_t);
  const double rs = (cos_i - n * cos_t) / (cos_i + n * cos_t);
  const double rp = (n * cos_i - cos_t) / (n * cos_i + cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

// The CIE 1931 2° matching functions, Wyman, Sloan & Shirley's multi-lobe fit (JCGT 2013): a fit
// in wavelength, independent of the Fourier-space Gaussians the model integrates with.
glm::dvec3 cie_1931(double nm) {
  auto g = [nm](double mu, double below, double above) {
    const double t = (nm - mu) / (nm < mu ? below : above);
    return std::exp(-0.5 * t * t);
  };
  return {1.056 * g(599.8, 37.9, 31.0) + 0.362 * g(442.0, 16.0, 26.7) -
              0.065 * g(501.1, 20.4, 26.2),
          0.821 * g(568.8, 46.9, 40.5) + 0.286 * g(530.9, 16.3, 31.1),
          1.217 * g(437.0, 11.8, 36.0) + 0.681 * g(459.0, 26.0, 13.8)};
}

// The reflectance of a film (IOR n2, d nm) on a base (IOR n3) seen from the air at wavelength nm,
// Airy's closed form with the interfaces' reflectances R12, R23 and their amplitudes' signs:
// reflecting off a higher IOR flips the wave.
double airy(double nm, double r12, double r23, double n2, double n3, double cos2, double d) {
  const double sign = (1.0 < n2 ? -1.0 : 1.0) * (n2 < n3 ? -1.0 : 1.0);
  const double a = sign * std::sqrt(r12 * r23);
  const double c = std::cos(2.0 * glm::pi<double>() * 2.0 * n2 * d * cos2 / nm);
  return (r12 + r23 + 2.0 * a * c) / (1.0 + r12 * r23 + 2.0 * a * c);
}

// The film's colour: each channel's spectrum (the base's IOR from its F0) integrated from 360 to
// 830 nm against the matching functions, each normalised to an equal-energy spectrum, taken to
// linear Rec. 709 and divided by what the equal-energy spectrum gives there (grey is grey).
glm::dvec3 spectral_film(double cos1, double n2, double d, const glm::dvec3& f0) {
  const glm::dmat3 xyz_to_rgb = glm::transpose(glm::dmat3(3.2404542, -1.5371385, -0.4985314,  //
                                                          -0.9692660, 1.8760108, 0.0415560,   //
                                                          0.0556434, -0.2040259, 1.0572252));
  const double r12 = fresnel(cos1, n2);
  const double cos2 = std::sqrt(1.0 - (1.0 - cos1 * cos1) / (n2 * n2));
  glm::dvec3 rgb;
  for (int ch = 0; ch < 3; ++ch) {
    const double root = std::sqrt(std::min(f0[ch], 0.9999));
    const double n3 = (1.0 + root) / (1.0 - root);
    const double r23 = fresnel(cos2, n3 / n2);
    glm::dvec3 xyz(0.0), white(0.0);
    for (int nm = 360; nm <= 830; ++nm) {
      const glm::dvec3 cmf = cie_1931(nm);
      xyz += airy(nm, r12, r23, n2, n3, cos2, d) * cmf;
      white += cmf;
    }
    const glm::dvec3 c = xyz_to_rgb * (xyz / white), w = xyz_to_rgb * glm::dvec3(1.0);
    rgb[ch] = std::clamp(c[ch] / w[ch], 0.0, 1.0);
  }
  return rgb;
}

}  // namespace

TEST_CASE("thin film: the Fresnel is the film's spectrum, integrated wavelength by wavelength") {
  // Over a dielectric within 0.012; over a metal (R23 near 1) within 0.045 down to cos 0.3: the
  // model's two harmonics leave more of the Airy sum out there (0.13 at cos 0.1).
  for (double d : {50.0, 150.0, 300.0, 450.0, 700.0})
    for (double film : {1.0, 1.2, 1.5, 2.0})  // the air's; below, at and above the base's 1.5
      for (double cos1 : {1.0, 0.7, 0.3, 0.1})
        for (const glm::dvec3& f0 : {glm::dvec3(0.04), glm::dvec3(0.95, 0.64, 0.54)}) {
          const bool metal = f0.x > 0.5;
          if (metal && cos1 < 0.3) continue;
          INFO("thickness " << d << " nm, film IOR " << film << ", cos " << cos1 << ", F0 "
                            << f0.x << " " << f0.y << " " << f0.z);
          const glm::dvec3 expected = spectral_film(cos1, film, d, f0);
          const glm::vec3 f = thin_film_fresnel(float(cos1), 1.f, float(film), float(d),
                                                glm::vec3(f0));
          for (int ch = 0; ch < 3; ++ch)
            CHECK(std::abs(f[ch] - expected[ch]) < (metal ? 0.045 : 0.012));
        }
}

TEST_CASE("thin film: a quarter-wave film cancels reflection, a film of the outside's IOR or of "
          "thickness 0 is not there") {
  // n2 = √n3 and n2 d = 550 / 4 at normal incidence: both interfaces reflect alike and the two
  // waves leave half a wave apart, so nothing is reflected at 550 nm (the direct computation
  // checks that it models this), and the film (an anti-reflection coating) leaves much less than
  // the bare glass's 0.04 in every channel.
  const double n2 = std::sqrt(1.5), d = 550.0 / (4.0 * n2);
  const double r12 = fresnel(1.0, n2), r23 = fresnel(1.0, 1.5 / n2);
  CHECK(airy(550.0, r12, r23, n2, 1.5, 1.0, d) == doctest::Approx(0.0).epsilon(1e-12));
  // A half-wave film is absent at its wavelength: the bare glass's (1 − 1.5)² / (1 + 1.5)².
  CHECK(airy(550.0, r12, r23, n2, 1.5, 1.0, 2.0 * d) == doctest::Approx(0.04).epsilon(1e-9));
  const glm::vec3 coated = thin_film_fresnel(1.f, 1.f, float(n2), float(d), glm::vec3(0.04f));
  for (int ch = 0; ch < 3; ++ch) CHECK(coated[ch] < 0.01f);
  CHECK(coated.y < 0.002f);  // green: near the minimum
  // Not there: the bare base's Fresnel reflectance (of the IOR its F0 gives).
  for (float cos1 : {1.f, 0.8f, 0.4f, 0.05f, 0.f})
    for (float f0 : {0.f, 0.04f, 0.3f, 0.9f}) {
      INFO("cos " << cos1 << ", F0 " << f0);
      const double n3 = (1.0 + std::sqrt(double(f0))) / (1.0 - std::sqrt(double(f0)));
      const float bare = float(fresnel(cos1, n3));
      for (float d : {0.f, 120.f, 400.f, 1500.f}) {
        const glm::vec3 f = thin_film_fresnel(cos1, 1.f, 1.f, d, glm::vec3(f0));
        for (int ch = 0; ch < 3; ++ch) CHECK(f[ch] == doctest::Approx(bare).epsilon(1e-4));
      }
      for (float film : {1.3f, 2.f}) {
        const glm::vec3 f = thin_film_fresnel(cos1, 1.f, film, 0.f, glm::vec3(f0));
        for (int ch = 0; ch < 3; ++ch) CHECK(f[ch] == doctest::Approx(bare).epsilon(1e-4));
      }
    }
}

TEST_CASE("thin film: the Fresnel stays in [0, 1] at every angle, thickness and IOR") {
  float lowest = 1.f, highest = 0.f;
  for (float cos1 = 0.f; cos1 <= 1.f; cos1 += 1.f / 64.f)
    for (float d : {0.f, 0.01f, 5.f, 20.f, 60.f, 100.f, 180.f, 250.f, 400.f, 600.f, 900.f, 2000.f,
                    1e5f, 1e30f})
      for (float film : {1.f, 1.05f, 1.3f, 1.5f, 1.8f, 2.5f, 4.f, 1e6f})
        for (float f0 : {0.f, 0.01f, 0.04f, 0.2f, 0.5f, 0.9f, 1.f}) {
          const glm::vec3 f = thin_film_fresnel(cos1, 1.f, film, d, glm::vec3(f0, 0.5f, 1.f - f0));
          for (int ch = 0; ch < 3; ++ch) {
            INFO("cos " << cos1 << ", thickness " << d << ", film IOR " << film << ", F0 " << f0);
            REQUIRE(f[ch] >= 0.f);
            REQUIRE(f[ch] <= 1.f);
            lowest = std::min(lowest, f[ch]), highest = std::max(highest, f[ch]);
          }
        }
  // (and covers both ends)
  CHECK(lowest == 0.f);
  CHECK(highest == 1.f);
}

namespace {

struct Film {
  BrdfParams params;
  float theta_o;
  std::string label() const {
    std::ostringstream s;
    s << "metallic " << params.metallic << ", roughness " << params.roughness << ", specular "
      << params.specular << ", transmission " << params.transmission << ", iridescence "
      << params.iridescence << " (IOR " << params.iridescence_ior << ", "
      << params.iridescence_thickness << " nm), clearcoat " << params.clearcoat << ", θo "
      << glm::degrees(theta_o) << "°";
    return s.str();
  }
};

BrdfParams film(float metallic, float roughness, float thickness, float film_ior) {
  BrdfParams p;
  p.base_color = {0.8f, 0.5f, 0.2f};
  p.metallic = metallic, p.roughness = roughness;
  p.iridescence = 1.f, p.iridescence_ior = film_ior, p.iridescence_thickness = thickness;
  return p;
}

std::vector<Film> configs() {
  std::vector<Film> c;
  for (float metallic : {0.f, 0.5f, 1.f})
    for (float roughness : {0.3f, 0.7f})
      for (float theta : {10.f, 50.f, 80.f})
        c.push_back({film(metallic, roughness, 300.f, 1.3f), glm::radians(theta)});
  BrdfParams p = film(0.f, 0.4f, 550.f, 2.f);
  p.iridescence = 0.6f, p.specular = 0.f;  // the film alone reflects
  c.push_back({p, glm::radians(30.f)});
  p = film(0.f, 0.4f, 200.f, 1.8f);
  p.clearcoat = 0.7f, p.clearcoat_roughness = 0.3f;
  c.push_back({p, glm::radians(40.f)});
  p = film(0.f, 0.5f, 350.f, 1.3f);
  p.transmission = 1.f;
  c.push_back({p, glm::radians(45.f)});
  return c;
}

}  // namespace

TEST_CASE("iridescent BRDF sampling follows its pdf (χ²), weights are eval · |cos| / pdf") {
  const auto all = configs();
  const double level = 1.0 - std::pow(1.0 - 0.01, 1.0 / double(all.size()));
  Pcg32 rng(31);
  for (size_t k = 0; k < all.size(); ++k) {
    const Film& c = all[k];
    INFO(c.label());
    const GltfBrdf brdf(c.params);
    CHECK_FALSE(brdf.lambertian());
    const glm::vec3 wo = direction(c.theta_o, 0.3f);
    CHECK(dacrt::test::brdf_chi2_p_value(brdf, brdf, wo, 5000 + k, 400000) > level);
    dacrt::test::check_sample_weights(brdf, wo, rng);
  }
}

TEST_CASE("iridescent BRDF is reciprocal and zero below the surface without transmission") {
  Pcg32 rng(33);
  for (Film c : configs()) {
    if (c.params.transmission > 0.f) continue;
    c.params.clearcoat = 0.f;  // (the coat's Fresnel is at the view only: not reciprocal)
    INFO(c.label());
    dacrt::test::check_reciprocal_reflection(GltfBrdf(c.params), rng, 1e-3f);
  }
}

TEST_CASE("iridescent BRDF: the specular lobes' Fresnel is mix(F, F_film, iridescence)") {
  const glm::vec3 wo = direction(glm::radians(50.f), 0.2f);
  const glm::vec3 wi = direction(glm::radians(20.f), 2.5f);
  const glm::vec3 h = glm::normalize(wo + wi);
  const float cos_h = glm::dot(wo, h);
  const float alpha = 0.4f * 0.4f;
  const float lobe = ggx_d(h.z, alpha) * ggx_visibility(wo.z, wi.z, alpha);
  const float m = 1.f - cos_h, w = m * m * m * m * m;
  // A metal: F = baseColor + (1 − baseColor) w, the film over F0 = baseColor.
  BrdfParams metal = film(1.f, 0.4f, 420.f, 1.7f);
  metal.iridescence = 0.75f;
  const glm::vec3 base = metal.base_color;
  const glm::vec3 f_metal = glm::mix(base + (1.f - base) * w,
                                     thin_film_fresnel(cos_h, 1.f, 1.7f, 420.f, base), 0.75f);
  const glm::vec3 got = GltfBrdf(metal).eval(wo, wi);
  for (int ch = 0; ch < 3; ++ch)
    CHECK(got[ch] == doctest::Approx(f_metal[ch] * lobe).epsilon(1e-5));
  // A dielectric with a black base (the specular lobe alone): F0 = 0.04 · specular.
  BrdfParams glass = film(0.f, 0.4f, 260.f, 1.2f);
  glass.base_color = glm::vec3(0.f), glass.specular = 0.5f;
  const float f0 = 0.04f * 0.5f, fd = f0 + (0.5f - f0) * w;
  const glm::vec3 f_glass =
      glm::mix(glm::vec3(fd), thin_film_fresnel(cos_h, 1.f, 1.2f, 260.f, glm::vec3(f0)), 1.f);
  const glm::vec3 got_glass = GltfBrdf(glass).eval(wo, wi);
  for (int ch = 0; ch < 3; ++ch)
    CHECK(got_glass[ch] == doctest::Approx(f_glass[ch] * lobe).epsilon(1e-4));
  // The diffuse base keeps 1 − max F: white Lambert under the film, far from the lobe.
  BrdfParams white = film(0.f, 0.05f, 260.f, 1.2f);
  white.base_color = glm::vec3(1.f);
  const glm::vec3 v = direction(glm::radians(30.f), 0.f), l = direction(glm::radians(10.f), 2.f);
  const float cos_vh = glm::dot(v, glm::normalize(v + l));
  const glm::vec3 f_film = thin_film_fresnel(cos_vh, 1.f, 1.2f, 260.f, glm::vec3(0.04f));
  const float diffuse = (1.f - std::max({f_film.x, f_film.y, f_film.z})) / glm::pi<float>();
  const glm::vec3 got_white = GltfBrdf(white).eval(v, l);
  for (int ch = 0; ch < 3; ++ch) CHECK(got_white[ch] == doctest::Approx(diffuse).epsilon(1e-3));
}

TEST_CASE("iridescent BRDF: the white furnace") {
  // A white metal and the specular layer over black never return more than they receive: F_film
  // is in [0, 1]. Over a white diffuse base the spec's rgb_mix weights the base by 1 − max F_film
  // at each direction's own V·H, and a film's F is not monotonic in angle (it can fall where
  // plain Fresnel rises), so, like fresnel_mix beyond 30° (brdf_test.cpp), it returns more than
  // it receives: up to 1.023 at 30° here (a film of IOR 2), as specified. It is held to 1.04.
  struct Case {
    glm::vec3 base;
    float metallic, specular, max_theta, bound;
  };
  for (const Case& c :
       {Case{glm::vec3(1.f), 1.f, 1.f, 89.f, 1.f}, Case{glm::vec3(0.f), 0.f, 1.f, 89.f, 1.f},
        Case{glm::vec3(1.f), 0.f, 1.f, 30.f, 1.04f}, Case{glm::vec3(1.f), 0.f, 0.f, 30.f, 1.04f}})
    for (float roughness : {0.f, 0.3f, 0.8f})
      for (float thickness : {80.f, 300.f, 700.f})
        for (float film_ior : {1.2f, 2.f})
          for (float theta : {0.f, 30.f, 60.f, 89.f}) {
            if (theta > c.max_theta) continue;
            BrdfParams p = film(c.metallic, roughness, thickness, film_ior);
            p.base_color = c.base, p.specular = c.specular;
            INFO("base " << c.base.x << ", metallic " << c.metallic << ", specular " << c.specular
                         << ", roughness " << roughness << ", " << thickness << " nm, film IOR "
                         << film_ior << ", θo " << theta);
            const auto [mean, error] =
                dacrt::test::brdf_albedo(GltfBrdf(p), direction(glm::radians(theta), 0.f), 41,
                                         50000);
            for (int ch = 0; ch < 3; ++ch) CHECK(mean[ch] <= c.bound + 4.0 * error[ch] + 1e-6);
          }
  // A smooth metal under a film is a mirror of the film's colour: seen from above, its albedo is
  // the film's Fresnel at normal incidence.
  const BrdfParams mirror = film(1.f, 0.f, 300.f, 1.5f);  // baseColor 0.8, 0.5, 0.2
  const auto [mean, error] = dacrt::test::brdf_albedo(GltfBrdf(mirror), glm::vec3(0, 0, 1), 43);
  const glm::vec3 f = thin_film_fresnel(1.f, 1.f, 1.5f, 300.f, mirror.base_color);
  for (int ch = 0; ch < 3; ++ch) CHECK(mean[ch] == doctest::Approx(f[ch]).epsilon(2e-3));
}

TEST_CASE("an iridescence or a film thickness of 0 leaves the BRDF exactly as without") {
  for (float metallic : {0.f, 0.4f, 1.f}) {
    BrdfParams plain = film(metallic, 0.5f, 400.f, 1.3f);
    plain.iridescence = 0.f;
    plain.transmission = metallic < 1.f ? 0.5f : 0.f;
    BrdfParams other_film = plain;
    other_film.iridescence_ior = 2.2f, other_film.iridescence_thickness = 150.f;
    BrdfParams no_thickness = plain;
    no_thickness.iridescence = 1.f, no_thickness.iridescence_thickness = 0.f;
    BrdfParams without;  // nothing of the extension set
    without.base_color = plain.base_color, without.metallic = metallic, without.roughness = 0.5f;
    without.transmission = plain.transmission;
    const GltfBrdf reference(without);
    Pcg32 rng(37);
    for (const BrdfParams& p : {plain, other_film, no_thickness}) {
      const GltfBrdf brdf(p);
      for (int k = 0; k < 500; ++k) {
        const glm::vec3 wo = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
        glm::vec3 wi = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
        if (k % 3 == 0) wi.z = -wi.z;  // transmission
        CHECK(brdf.eval(wo, wi) == reference.eval(wo, wi));
        CHECK(brdf.pdf(wo, wi) == reference.pdf(wo, wi));
        const float u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
        const auto a = brdf.sample(wo, u0, u1, u2), b = reference.sample(wo, u0, u1, u2);
        REQUIRE(a.has_value() == b.has_value());
        if (a) CHECK((a->wi == b->wi && a->weight == b->weight && a->pdf == b->pdf));
      }
    }
  }
  // Lambert stays Lambert without a film, and is not Lambert with one (the film reflects even
  // where the base does not: specular 0).
  BrdfParams lambert = film(0.f, 0.1f, 300.f, 1.3f);
  lambert.specular = 0.f, lambert.iridescence = 0.f;
  CHECK(GltfBrdf(lambert).lambertian());
  lambert.iridescence = 0.2f;
  CHECK_FALSE(GltfBrdf(lambert).lambertian());
  const glm::vec3 wo = direction(glm::radians(30.f), 0.f);
  const glm::vec3 mirrored = GltfBrdf(lambert).eval(wo, glm::vec3(-wo.x, -wo.y, wo.z));
  CHECK(mirrored.x + mirrored.y + mirrored.z > 10.f * lambert.base_color.x / glm::pi<float>());
}
