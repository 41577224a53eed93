// write_image(path, image, view=None, exposure=0.0): see image.h.
#include "image.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "dacrt/io/image_file.h"
#include "dacrt/util/error.h"
#include "studies.h"

namespace py = pybind11;

namespace dacrt::python {

namespace {

void write_image_array(const py::object& path_object, const py::array& array,
                       const std::optional<std::string>& view, double exposure) {
  const std::string path = path_argument(path_object, "path");
  if (array.dtype().kind() != 'f')
    throw py::type_error("write_image: image wants a float array (scene-linear values), not " +
                         std::string(py::str(array.dtype())));
  if (array.ndim() != 3 || (array.shape(2) != 3 && array.shape(2) != 4) || array.shape(0) < 1 ||
      array.shape(1) < 1) {
    std::string shape;
    for (py::ssize_t d = 0; d < array.ndim(); ++d)
      shape += (d ? ", " : "") + std::to_string(array.shape(d));
    const std::string wanted = "(height, width, 3) or (height, width, 4)";
    throw py::value_error("write_image: image wants shape " + wanted + ", not (" + shape + ")");
  }
  if (!std::isfinite(exposure))
    throw py::value_error("write_image: exposure= wants a finite number of stops");
  const ImageFormat format = output_format("path", path);
  if ((view || exposure != 0.0) && !holds_display_values(format))
    throw py::value_error("write_image: " + std::string(view ? "view=" : "exposure=") +
                          " changes only display values (PNG, JPEG), and " + path + " is " +
                          format_name(format) + " (scene-linear)");
  if (array.shape(0) > (1 << 15) || array.shape(1) > (1 << 15))
    throw py::value_error("write_image: an image side is at most 32768 pixels");
  const auto pixels = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(array);
  const int height = int(array.shape(0)), width = int(array.shape(1)),
            channels = int(array.shape(2));
  Image image(width, height);
  std::vector<float> alpha(channels == 4 ? size_t(width) * size_t(height) : 0);
  const float* data = pixels.data();
  for (size_t p = 0; p < size_t(width) * size_t(height); ++p) {
    for (int c = 0; c < 3; ++c) image.rgb[3 * p + c] = data[channels * p + c];
    if (channels == 4) alpha[p] = data[4 * p + 3];
  }
  const bool keep_alpha = format == ImageFormat::exr || format == ImageFormat::png;
  if (channels == 4 && !keep_alpha) {
    const std::string warning = "write_image: " + path + " is " + format_name(format) +
                                ", which holds no alpha: the fourth channel is not written";
    if (PyErr_WarnEx(PyExc_UserWarning, warning.c_str(), 1) < 0)
      throw py::error_already_set();  // warnings made errors
  }
  DisplayOptions display;
  display.view = view.value_or("");
  display.exposure = exposure;
  py::gil_scoped_release unlocked;
  write_image(path, image, display, {},
              keep_alpha ? std::span<const float>(alpha) : std::span<const float>(), "path");
}

}  // namespace

void add_image(py::module_& m) {
  m.def("write_image", &write_image_array, py::arg("path"), py::arg("image"),
        py::arg("view") = py::none(), py::arg("exposure") = 0.0,
        "write_image(path, image, view=None, exposure=0.0) -> None\n\n"
        "Writes a scene-linear image (a float numpy array of shape (height, width, 3), or 4 with "
        "alpha, such as render()'s) in the format its file name says: .exr (float RGB, alpha as "
        "A), .hdr (Radiance RGBE), .png (8-bit, with alpha) or .jpg/.jpeg, the last two through "
        "the display view (view=, a name of `dacrt views`; default sRGB) after scaling by "
        "2**exposure: the bytes `dacrt render --preview` and `dacrt convert` write. path: a str, "
        "bytes or os.PathLike. JPEG and HDR hold no alpha (a UserWarning says it is dropped). "
        "An unknown extension or a bad view raises ValueError, a file that cannot be written "
        "dacrt.Error. Written to a temporary name and renamed.");
}

}  // namespace dacrt::python
