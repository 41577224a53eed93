// `dacrt info SCENE [--scene N] [--animation NAME|INDEX|all]`: triangles, meshes, materials,
// lights, images, attributes, what is skipped, variants, animations, cameras (each as render
// flags), bounds and the work a render skips, on stdout.
#pragma once

#include <string>
#include <vector>

namespace dacrt {

// The command's exit code (0); throws UsageError or Error.
int info_main(const std::vector<std::string>& args);

}  // namespace dacrt
