// KHR_materials_sheen: the Charlie sheen lobe with the Charlie visibility (both Estevez & Kulla
// 2017, "Production Friendly Microfacet Sheen BRDF"), layered over the material by albedo scaling,
// exactly as the extension's implementation notes write them (materials/layers.h does the
// layering):
//   f_sheen = sheenColor · D(h) · V(wo, wi),  D(h) = (2 + 1/α) sin^(1/α) θh / (2π),
//   V = 1 / ((1 + Λ(cos θo) + Λ(cos θi)) · 4 cos θo cos θi),  α = sheenRoughness²
//   f = f_sheen + min(1 − max(sheenColor) · E(cos θo), 1 − max(sheenColor) · E(cos θi)) · f_base
// with Λ the paper's fitted shadowing (l(x) below: Λ(μ) = exp(l(μ)) for μ < ½, mirrored about ½
// above). The notes allow Ashikhmin's cheaper visibility, 1 / (4 (cos θi + cos θo − cos θi cos
// θo)), but it reflects more than it receives near grazing (E up to ~4 at roughness 0), so albedo
// scaling no longer conserves energy; Khronos's sample viewer, and its E table, use Charlie's.
// α is kept at sheen_min_alpha or above (the notes' sheenRoughness 0 is a lobe of zero width).
// E(μ, r) is the lobe's directional albedo for a white sheenColor: sheen_albedo() interpolates a
// table of it that sheen.cpp integrates once, on first use (see there for the quadrature); it
// stays below 1, so the albedo scaling needs no clamp. The lobe is sampled by cosine-weighted
// directions: it is broad at every roughness.
#pragma once

namespace dacrt {

constexpr float sheen_min_alpha = 0.01f;  // sheenRoughness 0.1: narrower lobes are as sharp

// α for a sheenRoughness in [0, 1].
float sheen_alpha(float roughness);
// The Charlie distribution at cos θh (0 at or below the horizon... it is symmetric: |cos θh|).
float sheen_d(float cos_h, float alpha);
// The Charlie visibility V = 1 / ((1 + Λ(co) + Λ(ci)) · 4 co ci), for ci, co > 0.
float sheen_visibility(float cos_o, float cos_i, float alpha);
// Its shadowing term Λ(cos θ) for a sheen of α.
float sheen_lambda(float cos_theta, float alpha);
// E(μ, roughness) = ∫ D V cos θi dωi over the upper hemisphere, for wo at cos θo = μ, from the
// table (bilinear in √μ and in log α, where its nodes are evenly spaced).
float sheen_albedo(float cos_o, float roughness);
// The same integral computed directly (the table's entries; and for the tests).
float sheen_albedo_integral(float cos_o, float roughness);

}  // namespace dacrt
