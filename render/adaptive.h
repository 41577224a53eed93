// Adaptive sampling (`--adaptive REL`): every pixel first takes the minimum number of samples;
// after each later pass, the pixels whose mean has converged stop taking samples, and the rest go
// on up to the samples asked. A pixel's k-th sample is the one a uniform render gives it (the
// numbers depend only on seed, pixel, sample and dimension), so a pixel that never stops is the
// uniform render's pixel, and which pixels stop is the same for any thread count.
//
// The error estimate, after a pass ending at sample n ≥ the minimum: a pixel's relative error is
// the standard error of its mean channel average (R+G+B)/3, from the film's sums of squares,
// over max(mean, floor); floor = a tenth of the image's mean, so that dark pixels are held to
// an absolute error (the tenth of the image's brightness) rather than a relative error a display
// would never show. A pixel stops when the largest relative error in its 3×3 window (its own and
// its eight neighbours', those that stopped counting with their last estimate) is below REL: a
// pixel whose samples happened to agree (all missed a small light) keeps sampling while its
// neighbours show the noise.
//
// Unbiased in the limit: as REL → 0 only pixels whose whole window showed no variance at all stop
// (a flat sky), every other pixel is the uniform render's, bit for bit;
// as spp → ∞ with the default minimum (spp/16) every pixel's sample count grows without bound, so
// every pixel converges to the value a uniform render converges to. At a fixed REL and spp the
// decision to stop reads the pixel's own samples, which biases a stopped pixel by about its
// remaining error (< REL of its mean, or of the floor).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "dacrt/film/film.h"
#include "dacrt/integrators/integrator.h"

namespace dacrt {

// The samples every pixel takes before any may stop: settings.adaptive_min, else max(16, spp/16),
// never more than spp.
uint32_t adaptive_min_spp(const RenderSettings& settings);

class AdaptiveSampling {
 public:
  AdaptiveSampling(const RenderSettings& settings, int width, int height);

  // Back to every pixel sampling (a render that starts again from sample 0).
  void reset();
  uint32_t min_spp() const { return min_spp_; }
  // The pixels that take the next pass's samples, in increasing order.
  std::span<const uint32_t> active() const { return active_; }

  // Where a pass that starts at sample `from` ends, at most `last`: up to the minimum in passes of
  // `pass`, then a quarter more samples a pass, so that pixels stop soon after they converge; as
  // few pixels remain, up to twice as many, so that a pass is two `wavefront`s of samples.
  // Where the passes after the minimum end decides when pixels may stop: it depends on the
  // settings and the pixels still sampling alone (not on --pass-spp), so that they decide the
  // image.
  uint32_t pass_end(uint32_t from, uint32_t last, uint32_t pass, uint64_t wavefront) const;

  // After a pass that ended at sample `end`: stops the active pixels that converged (none before
  // the minimum).
  void update(const Film& film, uint32_t end);

 private:
  double target_;
  uint32_t min_spp_;
  int width_, height_;
  std::vector<uint32_t> active_;
};

}  // namespace dacrt
