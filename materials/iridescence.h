// KHR_materials_iridescence's thin-film Fresnel: the reflectance, in linear Rec. 709 RGB, of a
// dielectric film (IOR film_ior, thickness in nm) between the outside (outside_ior) and a base
// whose normal-incidence reflectance is base_f0, at cos θ1 between the viewer and the microfacet
// normal. Belcour & Barla 2017, "A Practical Extension to Microfacet Theory for the Modeling of
// Varying Iridescence", as the extension's implementation notes approximate it: unpolarised
// reflectances at both interfaces, phase shifts of 0 or π, the base's IOR from its F0 (a
// dielectric's, for metals too), and the Airy sum integrated over the spectrum in Fourier space
// (the Gaussian fit of the CIE 1931 matching functions, terms m ≤ 2) then taken to RGB. The
// GltfBrdf mixes it into the Fresnel of its dielectric and metallic specular lobes:
// F = mix(F, thin_film_fresnel(...), iridescence).
//
// Where this departs from the notes, and why:
// - The interfaces reflect by Fresnel's equations (unpolarised), not Schlick's approximation of
//   them: Schlick's (1 − cos)⁵ makes an interface between equal IORs reflect away from normal
//   incidence, so a film of the base's IOR interfered with itself (0.035 off the spectrum at
//   cos 0.3) and a film of the air's was not the bare base.
// - The optical path difference is 2 · film_ior · thickness · cos θ2 (inside the film), as in
//   the paper and Khronos's sample viewer; the notes' cos θ1 is a typo.
// - The spectral terms are divided, per channel, by the RGB of an equal-energy spectrum
//   (M · (1, 1, 1) = (1.20, 0.95, 0.91)), as the constant term already is: a flat spectrum is
//   then grey, and the result is the RGB of the film's actual spectrum to within 0.012 over
//   dielectrics (0.045 over metals, whose R23 near 1 leaves more of the Airy sum past m = 2, at
//   cos θ1 ≥ 0.3; tests/iridescence_test.cpp integrates it wavelength by wavelength). Without
//   it, nearly flat spectra (thin or weakly reflecting films) turn red by up to 0.18.
// - R12 · R23 is not clamped from below (the notes clamp it at 1e-5), so a film of the outside's
//   IOR, or of thickness 0, is exactly the bare base's Fresnel reflectance.
// - The result is clamped to [0, 1] per channel (the truncated series, and spectra outside
//   Rec. 709's gamut, overshoot a little).
// - As in the sample viewer, the film's IOR fades to the outside's over thicknesses of 0 to 0.03
//   nm, so that no film and a vanishing film agree.
#pragma once

#include <glm/glm.hpp>

namespace dacrt {

glm::vec3 thin_film_fresnel(float cos_theta1, float outside_ior, float film_ior, float thickness_nm,
                            const glm::vec3& base_f0);

}  // namespace dacrt
