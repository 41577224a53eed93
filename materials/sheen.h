// KHR_materials_sheen: the Charlie sheen lobe (Estevez & Kulla 2017) with the visibility of
// Neubelt & Pettineo 2013 (Ashikhmin's), layered over the material by albedo scaling as the
// specification says (gltf_brdf.h does the layering):
//   f_sheen = sheenColor · D(h) · V(wo, wi),  D(h) = (2 + 1/α) sin^(1/α) θh / (2π),
//   V = 1 / (4 (cos θi + cos θo − cos θi cos θo)),  α = sheenRoughness² (at least sheen_min_alpha)
//   f = f_sheen / max(1, E) + (1 − max(sheenColor) · min(1, E)) · f_base,
//   E = max(E(cos θo), E(cos θi))
// (the specification's min(1 − c·E(V·N), 1 − c·E(L·N)), which keeps eval reciprocal). The lobe
// with this visibility reflects more than it receives near grazing when smooth (E up to ~1.6 at
// roughness 0): there it is divided by E, so the layer conserves energy everywhere. E(μ, r) is
// the lobe's directional albedo for a white sheenColor: sheen_albedo() interpolates a table of it
// that sheen.cpp integrates once, on first use (see there for the quadrature). The lobe is
// sampled by cosine-weighted directions: it is broad at every roughness.
#pragma once

namespace dacrt {

constexpr float sheen_min_alpha = 0.01f;  // sheenRoughness 0.1: narrower lobes are as sharp

// α for a sheenRoughness in [0, 1].
float sheen_alpha(float roughness);
// The Charlie distribution at cos θh (0 at or below the horizon... it is symmetric: |cos θh|).
float sheen_d(float cos_h, float alpha);
// Neubelt & Pettineo's visibility, V = 1 / (4 (ci + co − ci co)), for ci, co > 0.
float sheen_visibility(float cos_o, float cos_i);
// E(μ, roughness) = ∫ D V cos θi dωi over the upper hemisphere, for wo at cos θo = μ, from the
// table (bilinear in √μ and in log α, where its nodes are evenly spaced).
float sheen_albedo(float cos_o, float roughness);
// The same integral computed directly (the table's entries; and for the tests).
float sheen_albedo_integral(float cos_o, float roughness);

}  // namespace dacrt
