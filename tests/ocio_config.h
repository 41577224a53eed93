// A small OpenColorIO config for the tests that set $OCIO: scene_linear is "linear"; the default
// display "Test" has the views Gamma2 (a gamma 2.0 encoding, unlike the built-in sRGB curve, so a
// test sees which path was taken) and Raw (the identity); a second display "Other" has Half
// (linear × 0.5), so that DISPLAY/VIEW names are needed to reach it. And ScopedOcioEnv, which
// sets or unsets $OCIO for one scope.
#pragma once

#include <cstdlib>
#include <optional>
#include <string>

namespace dacrt::test {

// Sets or unsets $OCIO for one scope and puts the previous value back afterwards.
struct ScopedOcioEnv {
  std::optional<std::string> saved;
  explicit ScopedOcioEnv(const char* value) {
    if (const char* old = std::getenv("OCIO")) saved = old;
    if (value)
      setenv("OCIO", value, 1);
    else
      unsetenv("OCIO");
  }
  ~ScopedOcioEnv() {
    if (saved)
      setenv("OCIO", saved->c_str(), 1);
    else
      unsetenv("OCIO");
  }
};

inline constexpr const char* ocio_test_config = R"(ocio_profile_version: 2
roles:
  default: linear
  scene_linear: linear
displays:
  Test:
    - !<View> {name: Gamma2, colorspace: gamma2}
    - !<View> {name: Raw, colorspace: linear}
  Other:
    - !<View> {name: Half, colorspace: half}
colorspaces:
  - !<ColorSpace>
    name: linear
  - !<ColorSpace>
    name: gamma2
    from_reference: !<ExponentTransform> {value: 2, direction: inverse}
  - !<ColorSpace>
    name: half
    from_reference: !<MatrixTransform> {matrix: [0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 1]}
)";

}  // namespace dacrt::test
