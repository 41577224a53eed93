// The study report's page (bench/html_page.h): escaping, base64, the bar chart's geometry, and a
// page that needs nothing from elsewhere.
#include "bench/html_page.h"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "dacrt/util/error.h"

using namespace dacrt;
namespace fs = std::filesystem;

namespace {

std::span<const uint8_t> bytes(std::string_view s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

// The heights of the chart's bars, in order.
std::vector<double> bar_heights(const std::string& svg) {
  std::vector<double> heights;
  const std::regex bar("<rect x=\"[0-9]+\" y=\"[0-9.]+\" width=\"[0-9]+\" height=\"([0-9.]+)\"");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), bar); it != std::sregex_iterator();
       ++it)
    heights.push_back(std::stod((*it)[1]));
  return heights;
}

}  // namespace

TEST_CASE("html page: text is escaped, bytes are base64 (RFC 4648's vectors)") {
  CHECK(html_escape("<a href=\"x\">&'</a>") == "&lt;a href=&quot;x&quot;&gt;&amp;&#39;&lt;/a&gt;");
  CHECK(base64(bytes("")) == "");
  CHECK(base64(bytes("f")) == "Zg==");
  CHECK(base64(bytes("fo")) == "Zm8=");
  CHECK(base64(bytes("foo")) == "Zm9v");
  CHECK(base64(bytes("foob")) == "Zm9vYg==");
  CHECK(base64(bytes("fooba")) == "Zm9vYmE=");
  CHECK(base64(bytes("foobar")) == "Zm9vYmFy");
  const uint8_t high[] = {0xff, 0xfe, 0x80};
  CHECK(base64(high) == "//6A");
}

TEST_CASE("html page: a bar chart's bars are proportional, with whiskers only for intervals") {
  const std::string svg = bar_chart_svg(
      "Mrays/s", "Mrays/s", {"dacrt", "embree <4>"},
      {{"primary", {{10.0, 9.0, 11.0}, {20.0}}}, {"shadow", {{5.0}, {0, 0, 0, false}}}});
  const std::vector<double> h = bar_heights(svg);
  REQUIRE(h.size() == 3 + 2);  // three bars, then the legend's two swatches
  CHECK(h[1] == doctest::Approx(2.0 * h[0]).epsilon(0.01));
  CHECK(h[2] == doctest::Approx(0.5 * h[0]).epsilon(0.01));
  size_t whiskers = 0;
  for (size_t at = svg.find("<path"); at != std::string::npos; at = svg.find("<path", at + 1))
    ++whiskers;
  CHECK(whiskers == 1);
  CHECK(svg.find("embree &lt;4&gt;") != std::string::npos);
  CHECK(svg.find("embree <4>") == std::string::npos);
}

TEST_CASE("html page: self-contained (no script, no style sheet, no file from elsewhere)") {
  const fs::path dir = fs::temp_directory_path() / "dacrt-html-page-test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path png = dir / "tiny.png";
  std::ofstream(png, std::ios::binary) << "\x89PNG\r\n\x1a\n";  // the bytes only matter as bytes
  HtmlPage page("A <study>");
  page.heading("Backends");
  page.table({"backend", "s"}, {{"dacrt", "1.0"}, {"<embree>", "2.0"}});
  page.images({{"dacrt", png.string()}});
  page.figure("<?xml version=\"1.0\"?>\n" + bar_chart_svg("t", "a", {"x"}, {{"g", {{1.0}}}}), "plot");
  page.write((dir / "report").string());
  std::ifstream in(dir / "report" / "index.html");
  std::stringstream text;
  text << in.rdbuf();
  const std::string html = text.str();
  CHECK(html == page.html());
  CHECK(html.starts_with("<!DOCTYPE html>"));
  CHECK(html.find("<title>A &lt;study&gt;</title>") != std::string::npos);
  CHECK(html.find("<td>&lt;embree&gt;</td>") != std::string::npos);
  CHECK(html.find("src=\"data:image/png;base64,iVBORw0KGgo=\"") != std::string::npos);
  CHECK(html.find("<?xml") == std::string::npos);  // a prologue inside HTML is an error
  for (const char* remote : {"<script", "<link", "@import", "url(", "src=\"http", "href="})
    CHECK_MESSAGE(html.find(remote) == std::string::npos, remote);
  // Every http(s) string is the SVG namespace's name, which no browser fetches.
  for (size_t at = html.find("http"); at != std::string::npos; at = html.find("http", at + 1))
    CHECK(html.compare(at, 26, "http://www.w3.org/2000/svg") == 0);
  CHECK_THROWS_WITH_AS(page.images({{"x", (dir / "missing.png").string()}}),
                       doctest::Contains("missing.png"), Error);
  fs::remove_all(dir);
}

TEST_CASE("html page: many bars get narrower rather than the chart wider than a page") {
  std::vector<BarGroup> groups;
  for (int g = 0; g < 30; ++g) groups.push_back({std::to_string(g + 1), {{1.0}, {2.0}, {3.0, 2.5, 3.5}}});
  const std::string svg = bar_chart_svg("per bounce", "Mrays/s", {"a", "b", "c"}, groups);
  const std::smatch width = [&] {
    std::smatch m;
    std::regex_search(svg, m, std::regex("<svg [^>]*width=\"([0-9]+)\""));
    return m;
  }();
  REQUIRE(width.size() == 2);
  CHECK(std::stoi(width[1]) <= 64 + 880 + 16);
  const std::vector<double> h = bar_heights(svg);
  REQUIRE(h.size() == 90 + 3);
  CHECK(h[1] == doctest::Approx(2.0 * h[0]).epsilon(0.01));
  // Whiskers keep a cap on bars a few pixels wide.
  CHECK(svg.find("h-") == std::string::npos);
}
