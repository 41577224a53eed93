#include "dacrt/render/adaptive.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace dacrt {

namespace {
// The floor of the error's denominator, as a share of the image's mean (see adaptive.h).
constexpr double dark_floor = 0.1;

// Each pixel's relative error, before the 3×3 window (see adaptive.h).
std::vector<float> relative_errors(const Film& film) {
  const size_t n = film.pixels();
  std::vector<glm::dvec2> stats(n);
  tbb::parallel_for(size_t(0), n, [&](size_t p) { stats[p] = film.mean_and_error(p); });
  // Summed in pixel order: the floor, and so every decision, is the same for any thread count.
  double sum = 0.0;
  for (const glm::dvec2& m : stats) sum += m.x;
  const double floor = std::max(dark_floor * sum / double(std::max<size_t>(n, 1)), 1e-30);
  std::vector<float> error(n);
  // A pixel with fewer than two samples (the rest were NaN or inf) has no estimate yet.
  tbb::parallel_for(size_t(0), n, [&](size_t p) {
    error[p] = film.count(p) < 2 ? INFINITY : float(stats[p].y / std::max(stats[p].x, floor));
  });
  return error;
}
}  // namespace

uint32_t adaptive_min_spp(const RenderSettings& s) {
  const uint32_t spp = uint32_t(std::max(s.spp, 1));
  const uint32_t min = s.adaptive_min > 0 ? uint32_t(s.adaptive_min) : std::max(16u, spp / 16);
  return std::min(min, spp);
}

AdaptiveSampling::AdaptiveSampling(const RenderSettings& settings, int width, int height)
    : target_(settings.adaptive),
      min_spp_(adaptive_min_spp(settings)),
      width_(width),
      height_(height) {
  reset();
}

void AdaptiveSampling::reset() {
  active_.resize(size_t(width_) * size_t(height_));
  std::iota(active_.begin(), active_.end(), 0u);
}

uint32_t AdaptiveSampling::pass_end(uint32_t from, uint32_t last, uint32_t pass,
                                    uint64_t wavefront) const {
  uint64_t end;
  if (from < min_spp_) {
    end = std::min<uint64_t>(uint64_t(from) + pass, min_spp_);
  } else {
    // Every pass ends with the wavefront draining (its last paths alone in their batches): a
    // pass of two wavefronts' samples at least keeps that cost down once few pixels remain.
    const uint64_t full =
        (2 * wavefront + active_.size() - 1) / std::max<size_t>(active_.size(), 1);
    end = uint64_t(from) + std::clamp<uint64_t>(full, std::max(1u, from / 4), std::max(1u, from));
  }
  return uint32_t(std::min<uint64_t>(end, last));
}

void AdaptiveSampling::update(const Film& film, uint32_t end) {
  if (end < min_spp_ || active_.empty()) return;
  const std::vector<float> error = relative_errors(film);
  const int w = width_, h = height_;
  std::vector<uint8_t> stop(active_.size());
  tbb::parallel_for(size_t(0), active_.size(), [&](size_t k) {
    const int x = int(active_[k] % uint32_t(w)), y = int(active_[k] / uint32_t(w));
    float worst = 0.f;
    for (int v = std::max(y - 1, 0); v <= std::min(y + 1, h - 1); ++v)
      for (int u = std::max(x - 1, 0); u <= std::min(x + 1, w - 1); ++u)
        worst = std::max(worst, error[size_t(v) * size_t(w) + size_t(u)]);
    stop[k] = worst < target_;
  });
  size_t kept = 0;
  for (size_t k = 0; k < active_.size(); ++k)
    if (!stop[k]) active_[kept++] = active_[k];
  active_.resize(kept);
}

}  // namespace dacrt
