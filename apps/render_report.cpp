#include "apps/render_report.h"

#include <algorithm>
#include <filesystem>

#include "bench/html_page.h"

namespace fs = std::filesystem;

namespace dacrt {

std::string report_preview(const std::string& dir, const std::string& backend) {
  return (fs::path(dir) / (backend + ".png")).string();
}

void write_render_report(const std::string& dir, const std::string& what,
                         const std::vector<BackendRun>& runs) {
  HtmlPage page("dacrt render: " + what);
  std::vector<std::string> names;
  std::vector<HtmlPage::Image> images;
  for (const BackendRun& run : runs) {
    names.push_back(run.backend);
    images.push_back({run.backend, report_preview(dir, run.backend)});
  }
  page.heading("Images");
  page.images(images);

  page.heading("Rays per second");
  page.paragraph(
      "One render per backend, so no interval: `dacrt bench --report DIR` repeats each "
      "measurement and gives the median with its 95 % confidence interval. Every backend traces the "
      "same rays (the random numbers depend only on seed, pixel, sample and dimension).");
  std::vector<BarGroup> by_type;
  for (int t = 0; t < ray_type_count; ++t) {
    if (!runs[0].stats.by_type[size_t(t)].rays) continue;
    BarGroup g{std::string(to_string(RayType(t))), {}};
    for (const BackendRun& run : runs)
      g.bars.push_back({run.stats.by_type[size_t(t)].rays_per_second() * 1e-6});
    by_type.push_back(std::move(g));
  }
  page.figure(bar_chart_svg("Mrays/s per ray type", "Mrays/s", names, by_type),
              "Rays over the backend's seconds, per ray type: primary rays are coherent, bounce "
              "rays incoherent, shadow rays need any hit.");
  size_t depths = 0;
  for (const BackendRun& run : runs) depths = std::max(depths, run.stats.by_bounce.size());
  std::vector<BarGroup> by_bounce;
  for (size_t k = 0; k < depths; ++k) {
    BarGroup g{std::to_string(k + 1), {}};
    for (const BackendRun& run : runs) {
      const bool has = k < run.stats.by_bounce.size() && run.stats.by_bounce[k].rays;
      g.bars.push_back({has ? run.stats.by_bounce[k].rays_per_second() * 1e-6 : 0.0, NAN, NAN, has});
    }
    by_bounce.push_back(std::move(g));
  }
  if (!by_bounce.empty())
    page.figure(bar_chart_svg("Bounce rays: Mrays/s per bounce", "Mrays/s", names, by_bounce),
                "The bounce rays of each depth (1: the first bounce off the camera rays' hits): "
                "rays grow less coherent and batches smaller with depth.");

  // The rays of each depth are the same for every backend (the same paths): the first run's.
  std::vector<BarGroup> rays_by_depth;
  for (size_t k = 0; k < runs[0].stats.by_bounce.size(); ++k)
    rays_by_depth.push_back({std::to_string(k + 1), {{double(runs[0].stats.by_bounce[k].rays)}}});
  if (!rays_by_depth.empty())
    page.figure(bar_chart_svg("Bounce rays per depth", "rays", {"bounce rays"}, rays_by_depth),
                "How many bounce rays each depth has: the work the Mrays/s above weigh.");
  // The batches are the wavefront's, the same for every backend: the first run's.
  const std::vector<uint32_t>& batches = runs[0].stats.bounce_batches;
  if (!batches.empty()) {
    constexpr size_t most = 48;  // bars; longer renders show every k-th call
    const size_t step = (batches.size() + most - 1) / most;
    std::vector<BarGroup> calls;
    for (size_t i = 0; i < batches.size(); i += step)
      calls.push_back({std::to_string(i + 1), {{double(batches[i])}}});
    page.figure(bar_chart_svg("Bounce rays per backend call", "rays", {"bounce rays"}, calls),
                "The size of each call's batch of bounce rays, in order" +
                    std::string(step > 1 ? " (every " + std::to_string(step) + "th call)" : "") +
                    ": the wavefront keeps them full while new camera samples remain.");
  }

  page.heading("Table");
  std::vector<std::vector<std::string>> rows = comparison_rows(runs);
  std::vector<std::string> header = rows.front();
  header[0] = "";
  rows.erase(rows.begin());
  std::erase_if(rows, [](const std::vector<std::string>& r) { return r.empty(); });
  page.table(header, rows);
  page.write(dir);
}

}  // namespace dacrt
