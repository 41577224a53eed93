// HtmlPage: a study's report as one self-contained page, DIR/index.html, that any browser opens
// offline: images are embedded as data: URIs, plots are inline SVG drawn here, the style is in the
// page, and there is no script, no font and no file from anywhere else. `render --backend a,b,c
// --report DIR`, `bench --report DIR` and `converge -o DIR` write one.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace dacrt {

// Text made safe inside HTML and SVG elements and attribute values.
std::string html_escape(std::string_view text);
// RFC 4648 base64, with padding.
std::string base64(std::span<const uint8_t> bytes);

// A clustered bar chart as SVG: one cluster per group (a ray type, a bounce), one bar per series
// (a backend) in the series' order, each with its interval as a whisker when it has one.
struct Bar {
  double value = 0.0;
  double low = NAN, high = NAN;  // the interval (a whisker); NaN: none
  bool present = true;           // false: no bar (the series has no figure for this group)
};
struct BarGroup {
  std::string label;
  std::vector<Bar> bars;  // one per series
};
std::string bar_chart_svg(const std::string& title, const std::string& axis,
                          const std::vector<std::string>& series,
                          const std::vector<BarGroup>& groups);

class HtmlPage {
 public:
  explicit HtmlPage(std::string title);

  void heading(std::string_view text);
  void paragraph(std::string_view text);
  // Text shown as it is, in a fixed-width font (a table printed for a terminal).
  void preformatted(std::string_view text);
  // Cells are text (escaped); the header row is bold.
  void table(const std::vector<std::string>& header,
             const std::vector<std::vector<std::string>>& rows);
  // Images side by side, each with its caption: PNG files read now and embedded. Throws Error
  // naming a file that cannot be read.
  struct Image {
    std::string caption, png;
  };
  void images(const std::vector<Image>& images);
  // An SVG drawing, inlined (its XML prologue dropped), with a caption.
  void figure(std::string_view svg, std::string_view caption);

  std::string html() const;
  // Writes DIR/index.html (DIR created when missing), atomically; throws Error on failure.
  void write(const std::string& dir) const;

  // DIR/index.html: the file write(DIR) writes.
  static std::string file_in(const std::string& dir);
  // Makes DIR and its parents (a --report directory, before any work is done) and returns
  // file_in(DIR); throws Error naming DIR when it cannot.
  static std::string make_directory(const std::string& dir);

 private:
  std::string title_, body_;
};

}  // namespace dacrt
