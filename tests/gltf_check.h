// check_error: loading a broken glTF file must throw one dacrt::Error line naming the file and
// the element at fault.
#pragma once

#include <doctest/doctest.h>

#include <initializer_list>
#include <string>

#include "dacrt/io/gltf.h"
#include "dacrt/util/error.h"

namespace dacrt::test {

// Loading `path` must throw dacrt::Error with one line naming the file and containing `words`.
inline void check_error(const std::string& path, std::initializer_list<std::string> words,
                        GltfOptions options = {}) {
  try {
    load_gltf(path, options);
    FAIL("no error for " << path);
  } catch (const Error& e) {
    std::string message = e.what();
    INFO("message: " << message);
    CHECK(message.find(path) != std::string::npos);
    CHECK(message.find('\n') == std::string::npos);
    for (const std::string& word : words) CHECK(message.find(word) != std::string::npos);
  }
}

}  // namespace dacrt::test
