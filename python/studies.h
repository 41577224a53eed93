// The Python module's bench() and converge(): `dacrt bench` and `dacrt converge` from keyword
// arguments, their results as plain Python data (dicts and lists of numbers and strings).
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

namespace dacrt::python {

// Keyword arguments as command-line options: name → --name-with-dashes, True → the bare flag
// (False and None: left out), a list or tuple → its items joined by commas (or repeated as
// separate options for a name in `repeated`), numbers as Python prints them (which reads back
// exactly); progress=True shows the command's progress on stderr, which is --quiet otherwise.
// TypeError for a name in `refused` (and quiet=), saying why (`why`).
std::vector<std::string> keyword_options(const pybind11::kwargs& kwargs,
                                         const std::vector<std::string>& refused,
                                         const std::string& why,
                                         const std::vector<std::string>& repeated = {});

void add_studies(pybind11::module_& m);

}  // namespace dacrt::python
