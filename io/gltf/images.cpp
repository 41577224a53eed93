// glTF textures, samplers and images: the wrap modes and filter of each texture a material uses,
// and its image's encoded bytes (embedded, in a bufferView or an external file), decoded once
// per distinct source, in parallel, within a bound on the decoded size. A texture's image is its
// EXT_texture_webp source when it has one, else its source; a KHR_texture_basisu texture (KTX2,
// which this version cannot decode) falls back to its source, or is an error without one.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <unordered_map>

#include "dacrt/io/gltf/internal.h"
#include "dacrt/io/texture_decode.h"

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

// The encoded bytes of image i (called `what` in messages): its bufferView, or what tinygltf (or
// file.cpp, for data URIs it does not know) read from its URI.
std::pair<const unsigned char*, size_t> image_bytes(const Gltf& gltf, size_t i,
                                                    const std::string& what) {
  const tinygltf::Image& image = gltf.model.images[i];
  if (image.bufferView != -1) {
    const Span span = buffer_view(gltf, image.bufferView, what);
    return {span.data, span.size};
  }
  if (image.image.empty())
    gltf.fail(what + (image.uri.rfind("data:", 0) == 0
                          ? " cannot be read (its data URI is empty or not base64)"
                          : " cannot be read (missing or empty file)"));
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

int extension_source(const tinygltf::Texture& t, const char* name) {
  auto x = t.extensions.find(name);
  if (x == t.extensions.end() || !x->second.Has("source")) return -1;
  return x->second.Get("source").GetNumberAsInt();
}

void load_textures(const Gltf& gltf, const std::vector<bool>& texture_used, Scene& scene) {
  std::vector<bool> image_used(gltf.model.images.size(), false);
  std::vector<bool> falls_back(gltf.model.textures.size(), false);  // from KHR_texture_basisu
  scene.textures.resize(gltf.model.textures.size());
  for (size_t i = 0; i < gltf.model.textures.size(); ++i) {
    if (!texture_used[i]) continue;
    const tinygltf::Texture& src = gltf.model.textures[i];
    const std::string what = "texture " + str(i);
    Texture& t = scene.textures[i];
    // io/gltf/file.cpp's used_images reads the same image.
    const int webp = extension_source(src, "EXT_texture_webp");
    const int source = webp != -1 ? webp : src.source;
    const int ktx2 = webp != -1 ? -1 : extension_source(src, "KHR_texture_basisu");
    if (ktx2 != -1 && (source == -1 || source == ktx2))
      gltf.fail(what + " has only a KHR_texture_basisu image (KTX2), and this version has no " +
                "KTX2 decoder (the texture has no PNG, JPEG or WebP source to fall back to)");
    // (Textures without any source are never marked used: materials.cpp's texture_ref skips them.)
    if (source < 0 || size_t(source) >= gltf.model.images.size())
      gltf.fail(what + " refers to image " + str(source) + ", which does not exist (" +
                str(gltf.model.images.size()) + " images)");
    falls_back[i] = ktx2 != -1;
    scene.ignored.ktx2_textures += falls_back[i];
    t.image = uint32_t(source);
    image_used[size_t(source)] = true;
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
  // Each image as messages name it; a fallback for a KTX2 image names its texture too.
  std::vector<std::string> names(gltf.model.images.size());
  for (size_t i : used) names[i] = image_name(gltf, i);
  std::vector<bool> named_texture(gltf.model.images.size(), false);
  for (size_t t = 0; t < scene.textures.size(); ++t) {
    const uint32_t i = scene.textures[t].image;
    if (!falls_back[t] || named_texture[i]) continue;
    names[i] += ", the fallback of texture " + str(t) +
                "'s KHR_texture_basisu image (this version has no KTX2 decoder),";
    named_texture[i] = true;
  }
  scene.images.resize(gltf.model.images.size());
  // The sizes first, so that the whole set is bounded before anything is decoded.
  constexpr uint64_t kMaxDecodedBytes = uint64_t(1) << 32;
  uint64_t total = 0;
  for (size_t i : used) {
    const auto [data, size] = image_bytes(gltf, i, names[i]);
    total += decoded_size(data, size, gltf.path + ": " + names[i]);
  }
  if (total > kMaxDecodedBytes)
    gltf.fail("its images would take " + str(total >> 20) + " MiB decoded, more than the " +
              str(kMaxDecodedBytes >> 20) + " MiB limit");
  // In parallel. Reported: the first header error in image order (above), else the first
  // decoding error in image order. Images are decoded straight into what is kept; on top of
  // it, a progressive JPEG being decoded holds its coefficients (2 bytes a sample) and a
  // lossless WebP its texels again (4 bytes each), per thread.
  std::vector<std::string> errors(used.size());
  tbb::parallel_for(size_t(0), used.size(), [&](size_t k) {
    const size_t i = used[k];
    try {
      const auto [data, size] = image_bytes(gltf, i, names[i]);
      scene.images[i] = decode_image(data, size, gltf.path + ": " + names[i]);
    } catch (const Error& e) {
      errors[k] = e.what();
    }
  });
  for (const std::string& e : errors)
    if (!e.empty()) throw Error(e);
}

}  // namespace dacrt::gltf
