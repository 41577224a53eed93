// Reading a glTF file into tinygltf's model: .gltf or .glb (told apart by the GLB magic), with
// the checks tinygltf lacks (GLB chunk lengths, JSON nesting depth, the glTF schema's types and
// ranges (io/gltf/schema.h), FIFOs posing as buffers), external buffers read only as far as their
// byteLength, and only the images the render of scene `scene` can use read (their bytes are kept
// encoded; io/gltf/images.cpp decodes them). Throws dacrt::Error with one line naming the file.
#pragma once

#include <tiny_gltf.h>

#include <string>
#include <vector>

#include "dacrt/util/file_hash.h"

namespace dacrt {

// `scene` is the scene to be rendered (-1: the file's default), `variant` the
// KHR_materials_variants variant its primitives take their materials from (empty: their own).
// `files`, when given, receives the external files the file names and tinygltf finds (buffers,
// images) with the bytes read of each (a buffer's byteLength; none of an image the render does
// not use).
tinygltf::Model read_gltf_model(const std::string& path, int scene = -1,
                                std::vector<FileRead>* files = nullptr,
                                const std::string& variant = "");
// The same from bytes already in memory; `path` names them in messages, and external buffers are
// looked up beside it.
tinygltf::Model parse_gltf_model(const std::string& path, const unsigned char* data, size_t size,
                                 int scene = -1, std::vector<FileRead>* files = nullptr,
                                 const std::string& variant = "");

}  // namespace dacrt
