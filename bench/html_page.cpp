#include "bench/html_page.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <system_error>

#include "dacrt/util/atomic_file.h"
#include "dacrt/util/error.h"

namespace fs = std::filesystem;

namespace dacrt {

std::string html_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  return out;
}

std::string base64(std::span<const uint8_t> bytes) {
  static constexpr char digits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const size_t n = std::min<size_t>(3, bytes.size() - i);
    uint32_t v = uint32_t(bytes[i]) << 16;
    if (n > 1) v |= uint32_t(bytes[i + 1]) << 8;
    if (n > 2) v |= bytes[i + 2];
    for (size_t k = 0; k < 4; ++k) out += k <= n ? digits[v >> (18 - 6 * k) & 63] : '=';
  }
  return out;
}

namespace {

std::string number(double v, const char* format = "%g") {
  char s[48];
  std::snprintf(s, sizeof s, format, v);
  return s;
}

// The axis' step: 1, 2 or 5 × 10^k, about five of them up to `top`.
double tick_step(double top) {
  const double raw = top / 5.0, decade = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 5.0})
    if (m * decade >= raw) return m * decade;
  return 10.0 * decade;
}

// Okabe and Ito's eight colours, told apart by colour-blind readers too.
constexpr const char* palette[] = {"#0072B2", "#E69F00", "#009E73", "#CC79A7",
                                   "#56B4E9", "#D55E00", "#F0E442", "#000000"};

}  // namespace

std::string bar_chart_svg(const std::string& title, const std::string& axis,
                          const std::vector<std::string>& series,
                          const std::vector<BarGroup>& groups) {
  double top = 0.0;
  for (const BarGroup& g : groups)
    for (const Bar& b : g.bars)
      if (b.present && std::isfinite(b.value))
        top = std::max({top, b.value, std::isfinite(b.high) ? b.high : 0.0});
  if (!(top > 0.0)) top = 1.0;
  const double step = tick_step(top);
  top = std::ceil(top / step) * step;
  const int left = 64, right = 16, plot_top = 40, plot_height = 220, label_height = 40;
  // Bars 18 pixels wide 24 apart, narrower when many would make the chart wider than a page's
  // 880 pixels (then scaled down, its text with it, past legibility).
  const int bars = std::max<int>(1, int(groups.size() * std::max<size_t>(series.size(), 1)));
  int bar_width = 18, gap = 24;
  if (bars * bar_width + (int(groups.size()) + 1) * gap > 880) {
    gap = 8;
    bar_width = std::max(3, (880 - (int(groups.size()) + 1) * gap) / bars);
  }
  const int cluster = int(series.size()) * bar_width;
  const int plot_width = std::max(240, int(groups.size()) * (cluster + gap) + gap);
  const int legend_columns = int(std::min<size_t>(series.size(), 4));
  const int width = std::max(left + plot_width + right, left + 150 * legend_columns);
  const int legend_y = plot_top + plot_height + label_height;
  const int height = legend_y + 20 * int((series.size() + 3) / 4) + 8;
  const auto y_of = [&](double v) { return plot_top + plot_height * (1.0 - std::max(0.0, v) / top); };
  std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(width) +
                  "\" height=\"" + std::to_string(height) + "\" viewBox=\"0 0 " +
                  std::to_string(width) + " " + std::to_string(height) +
                  "\" style=\"font-family: sans-serif; font-size: 11px\">\n";
  s += "<title>" + html_escape(title) + "</title>\n";
  s += "<text x=\"" + std::to_string(width / 2) + "\" y=\"16\" text-anchor=\"middle\" " +
       "font-size=\"13\">" + html_escape(title) + "</text>\n";
  s += "<text transform=\"translate(14," + std::to_string(plot_top + plot_height / 2) +
       ") rotate(-90)\" text-anchor=\"middle\">" + html_escape(axis) + "</text>\n";
  for (double v = 0.0; v <= top * (1.0 + 1e-9); v += step) {
    const std::string y = number(y_of(v), "%.1f");
    s += "<line x1=\"" + std::to_string(left) + "\" x2=\"" + std::to_string(left + plot_width) +
         "\" y1=\"" + y + "\" y2=\"" + y + "\" stroke=\"#ddd\"/>\n";
    s += "<text x=\"" + std::to_string(left - 4) + "\" y=\"" + y +
         "\" dy=\"4\" text-anchor=\"end\">" + number(v) + "</text>\n";
  }
  for (size_t g = 0; g < groups.size(); ++g) {
    const int x0 = left + gap + int(g) * (cluster + gap);
    for (size_t k = 0; k < groups[g].bars.size() && k < series.size(); ++k) {
      const Bar& b = groups[g].bars[k];
      if (!b.present || !std::isfinite(b.value)) continue;
      const int x = x0 + int(k) * bar_width;
      const double y = y_of(b.value);
      s += "<rect x=\"" + std::to_string(x) + "\" y=\"" + number(y, "%.1f") + "\" width=\"" +
           std::to_string(std::max(1, bar_width - 2)) + "\" height=\"" +
           number(plot_top + plot_height - y, "%.1f") + "\" fill=\"" + palette[k % 8] +
           "\"><title>" + html_escape(series[k] + ", " + groups[g].label + ": " + number(b.value)) +
           "</title></rect>\n";
      if (!std::isfinite(b.low) || !std::isfinite(b.high)) continue;
      const std::string cx = std::to_string(x + bar_width / 2 - 1);
      const std::string lo = number(y_of(b.low), "%.1f"), hi = number(y_of(b.high), "%.1f");
      const int cap = std::max(2, bar_width - 8), cap_x = x + bar_width / 2 - 1 - cap / 2;
      s += "<path d=\"M" + cx + " " + lo + "V" + hi + "M" + std::to_string(cap_x) + " " + lo +
           "h" + std::to_string(cap) + "M" + std::to_string(cap_x) + " " + hi + "h" +
           std::to_string(cap) + "\" stroke=\"#000\" fill=\"none\"/>\n";
    }
    s += "<text x=\"" + std::to_string(x0 + cluster / 2) + "\" y=\"" +
         std::to_string(plot_top + plot_height + 16) + "\" text-anchor=\"middle\">" +
         html_escape(groups[g].label) + "</text>\n";
  }
  s += "<line x1=\"" + std::to_string(left) + "\" x2=\"" + std::to_string(left + plot_width) +
       "\" y1=\"" + std::to_string(plot_top + plot_height) + "\" y2=\"" +
       std::to_string(plot_top + plot_height) + "\" stroke=\"#000\"/>\n";
  for (size_t k = 0; k < series.size(); ++k) {
    const int x = left + int(k) % legend_columns * 150;
    const int y = legend_y + 20 * (int(k) / legend_columns);
    s += "<rect x=\"" + std::to_string(x) + "\" y=\"" + std::to_string(y - 10) +
         "\" width=\"12\" height=\"12\" fill=\"" + palette[k % 8] + "\"/><text x=\"" +
         std::to_string(x + 16) + "\" y=\"" + std::to_string(y) + "\">" + html_escape(series[k]) +
         "</text>\n";
  }
  return s + "</svg>\n";
}

HtmlPage::HtmlPage(std::string title) : title_(std::move(title)) {}

void HtmlPage::heading(std::string_view text) { body_ += "<h2>" + html_escape(text) + "</h2>\n"; }

void HtmlPage::paragraph(std::string_view text) { body_ += "<p>" + html_escape(text) + "</p>\n"; }

void HtmlPage::preformatted(std::string_view text) {
  body_ += "<pre>" + html_escape(text) + "</pre>\n";
}

void HtmlPage::table(const std::vector<std::string>& header,
                     const std::vector<std::vector<std::string>>& rows) {
  body_ += "<div class=\"table\"><table>\n<tr>";
  for (const std::string& h : header) body_ += "<th>" + html_escape(h) + "</th>";
  body_ += "</tr>\n";
  for (const auto& row : rows) {
    body_ += "<tr>";
    for (const std::string& cell : row) body_ += "<td>" + html_escape(cell) + "</td>";
    body_ += "</tr>\n";
  }
  body_ += "</table></div>\n";
}

void HtmlPage::images(const std::vector<Image>& images) {
  // A preview is a few MB at most; a file far larger is not one of ours.
  constexpr uintmax_t max_bytes = uintmax_t(1) << 28;
  body_ += "<div class=\"images\">\n";
  for (const Image& image : images) {
    std::error_code ec;
    const uintmax_t size = fs::file_size(image.png, ec);
    if (ec || size > max_bytes)
      throw Error("cannot embed " + image.png + " in the report: " +
                  (ec ? ec.message() : "larger than 256 MiB"));
    std::ifstream in(image.png, std::ios::binary);
    std::vector<uint8_t> bytes(size);
    if (!in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size)))
      throw Error("cannot embed " + image.png + " in the report: it cannot be read");
    body_ += "<figure><img alt=\"" + html_escape(image.caption) + "\" src=\"data:image/png;base64," +
             base64(bytes) + "\"><figcaption>" + html_escape(image.caption) +
             "</figcaption></figure>\n";
  }
  body_ += "</div>\n";
}

void HtmlPage::figure(std::string_view svg, std::string_view caption) {
  if (const size_t start = svg.find("<svg"); start != std::string_view::npos)
    svg.remove_prefix(start);
  body_ += "<figure>";
  body_ += svg;
  body_ += "<figcaption>" + html_escape(caption) + "</figcaption></figure>\n";
}

std::string HtmlPage::html() const {
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" +
         html_escape(title_) +
         "</title>\n<style>\n"
         "body { font-family: sans-serif; margin: 2em; max-width: 80em; }\n"
         "table { border-collapse: collapse; margin: 1em 0; }\n"
         "th, td { border: 1px solid #bbb; padding: 0.25em 0.6em; text-align: right; }\n"
         "th:first-child, td:first-child { text-align: left; }\n"
         "th, td { white-space: nowrap; }\n"
         ".table { overflow-x: auto; }\n"
         ".images { display: flex; flex-wrap: wrap; gap: 1em; }\n"
         "figure { margin: 0.5em 0; }\n"
         "figcaption { font-size: small; color: #444; }\n"
         "pre { white-space: pre-wrap; }\n"
         "img { image-rendering: pixelated; height: 16em; width: auto; border: 1px solid #ccc; }\n"
         "figure svg { max-width: 100%; height: auto; }\n"
         "</style>\n</head>\n<body>\n<h1>" +
         html_escape(title_) + "</h1>\n" + body_ + "</body>\n</html>\n";
}

std::string HtmlPage::file_in(const std::string& dir) {
  return (fs::path(dir) / "index.html").string();
}

std::string HtmlPage::make_directory(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw Error("--report: cannot create " + dir + ": " + ec.message());
  return file_in(dir);
}

void HtmlPage::write(const std::string& dir) const {
  const std::string path = make_directory(dir), page = html();
  write_atomically(path, "report", [&](std::ostream& out) { out << page; });
}

}  // namespace dacrt
