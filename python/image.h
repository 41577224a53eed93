// The Python module's write_image(): a numpy image written in the format its file name says
// (io/image_file.h), as `dacrt render -o` and `dacrt convert` write it.
#pragma once

#include <pybind11/pybind11.h>

namespace dacrt::python {

void add_image(pybind11::module_& m);

}  // namespace dacrt::python
