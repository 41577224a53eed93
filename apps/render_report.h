// `dacrt render --backend a,b,c --report DIR`: the comparison as a page (bench/html_page.h), the
// backends' images side by side, the table printed on stdout, and plots of what each backend
// made of each kind of ray.
#pragma once

#include <string>
#include <vector>

#include "apps/report.h"

namespace dacrt {

// The preview written into the report's directory for a backend: DIR/NAME.png.
std::string report_preview(const std::string& dir, const std::string& backend);
// Writes DIR/index.html; `what` describes the render in the title ("scene.gltf, 256×256, 16 spp").
void write_render_report(const std::string& dir, const std::string& what,
                         const std::vector<BackendRun>& runs);

}  // namespace dacrt
