// glTF textures, samplers and images: the wrap modes and filter of each texture a material uses,
// and its image's encoded bytes (embedded, in a bufferView or an external file), decoded once
// per distinct source, in parallel, within a bound on the decoded size.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <unordered_map>

#include "io/gltf/internal.h"
#include "io/texture_decode.h"

namespace dacrt::gltf {
namespace {

// "image N (uri or name)", for messages.
std::string image_name(const Gltf& gltf, size_t i) {
  const tinygltf::Image& image = gltf.model.images[i];
  std::string what = "image " + str(i);
  if (!image.uri.empty() && image.uri.rfind("data:", 0) != 0)
    what += " (" + one_line(image.uri.substr(0, 200)) + ")";
  else if (!image.name.empty())
    what += " (" + one_line(image.name.substr(0, 200)) + ")";
  return what;
}

// The encoded bytes of image i: its bufferView, or what tinygltf read from its URI.
std::pair<const unsigned char*, size_t> image_bytes(const Gltf& gltf, size_t i) {
  const tinygltf::Image& image = gltf.model.images[i];
  if (image.bufferView != -1) {
    const Span span = buffer_view(gltf, image.bufferView, image_name(gltf, i));
    return {span.data, span.size};
  }
  if (image.image.empty())
    gltf.fail(image_name(gltf, i) + " cannot be read (missing or empty file)");
  return {image.image.data(), image.image.size()};
}

// The bufferView, or a hash of the encoded bytes (FNV-1a).
uint64_t source_hash(const Gltf& gltf, size_t i) {
  const tinygltf::Image& image = gltf.model.images[i];
  if (image.bufferView != -1) return uint64_t(image.bufferView);
  uint64_t h = 0xcbf29ce484222325ull ^ image.image.size();
  for (unsigned char c : image.image) h = (h ^ c) * 0x100000001b3ull;
  return h | (uint64_t(1) << 63);  // apart from bufferView indices
}

bool same_source(const Gltf& gltf, size_t a, size_t b) {
  const tinygltf::Image &x = gltf.model.images[a], &y = gltf.model.images[b];
  if (x.bufferView != -1 || y.bufferView != -1) return x.bufferView == y.bufferView;
  return !x.image.empty() && x.image == y.image;
}

Wrap wrap_mode(const Gltf& gltf, int mode, const std::string& what) {
  switch (mode) {
    case TINYGLTF_TEXTURE_WRAP_REPEAT:
      return Wrap::repeat;
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
      return Wrap::clamp;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
      return Wrap::mirror;
  }
  gltf.fail(what + " is " + str(mode) + ", not 10497, 33071 or 33648");
}

}  // namespace

void load_textures(const Gltf& gltf, const std::vector<bool>& texture_used, Scene& scene) {
  std::vector<bool> image_used(gltf.model.images.size(), false);
  scene.textures.resize(gltf.model.textures.size());
  for (size_t i = 0; i < gltf.model.textures.size(); ++i) {
    if (!texture_used[i]) continue;
    const tinygltf::Texture& src = gltf.model.textures[i];
    const std::string what = "texture " + str(i);
    Texture& t = scene.textures[i];
    if (src.source < 0 || size_t(src.source) >= gltf.model.images.size())
      gltf.fail(what + (src.source == -1
                            ? " has no PNG or JPEG source image"
                            : " refers to image " + str(src.source) + ", which does not exist (" +
                                  str(gltf.model.images.size()) + " images)"));
    t.image = uint32_t(src.source);
    image_used[size_t(src.source)] = true;
    if (src.sampler != -1) {
      if (src.sampler < 0 || size_t(src.sampler) >= gltf.model.samplers.size())
        gltf.fail(what + " refers to sampler " + str(src.sampler) + ", which does not exist");
      const tinygltf::Sampler& sampler = gltf.model.samplers[size_t(src.sampler)];
      const std::string where = "sampler " + str(src.sampler);
      t.wrap_s = wrap_mode(gltf, sampler.wrapS, where + " wrapS");
      t.wrap_t = wrap_mode(gltf, sampler.wrapT, where + " wrapT");
      t.nearest = sampler.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
    }
  }
  // Images with the same encoded bytes (or bufferView) are decoded once: textures point at the
  // first of them.
  std::vector<size_t> used, first(gltf.model.images.size());
  std::unordered_map<uint64_t, std::vector<size_t>> by_source;  // source hash → images
  for (size_t i = 0; i < image_used.size(); ++i) {
    if (!image_used[i]) continue;
    std::vector<size_t>& bucket = by_source[source_hash(gltf, i)];
    auto same = std::find_if(bucket.begin(), bucket.end(),
                             [&](size_t j) { return same_source(gltf, j, i); });
    first[i] = same == bucket.end() ? i : *same;
    if (first[i] == i) used.push_back(i), bucket.push_back(i);
  }
  for (size_t t = 0; t < scene.textures.size(); ++t)
    if (texture_used[t]) scene.textures[t].image = uint32_t(first[scene.textures[t].image]);
  scene.images.resize(gltf.model.images.size());
  // The sizes first, so that the whole set is bounded before anything is decoded.
  constexpr uint64_t kMaxDecodedBytes = uint64_t(1) << 32;
  uint64_t total = 0;
  for (size_t i : used) {
    const auto [data, size] = image_bytes(gltf, i);
    total += decoded_size(data, size, gltf.path + ": " + image_name(gltf, i));
  }
  if (total > kMaxDecodedBytes)
    gltf.fail("its images would take " + str(total >> 20) + " MiB decoded, more than the " +
              str(kMaxDecodedBytes >> 20) + " MiB limit");
  // In parallel. Reported: the first header error in image order (above), else the first
  // decoding error in image order. Images are decoded straight into what is kept; on top of
  // it, a progressive JPEG being decoded holds its coefficients (2 bytes a sample) per thread.
  std::vector<std::string> errors(used.size());
  tbb::parallel_for(size_t(0), used.size(), [&](size_t k) {
    const size_t i = used[k];
    try {
      const auto [data, size] = image_bytes(gltf, i);
      scene.images[i] = decode_image(data, size, gltf.path + ": " + image_name(gltf, i));
    } catch (const Error& e) {
      errors[k] = e.what();
    }
  });
  for (const std::string& e : errors)
    if (!e.empty()) throw Error(e);
}

}  // namespace dacrt::gltf
