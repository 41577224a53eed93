// The Python module's bench() and converge(): `dacrt bench` and `dacrt converge` from keyword
// arguments, their results as plain Python data (dicts and lists of numbers and strings).
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

namespace dacrt::python {

// Keyword arguments as command-line options: name → --name-with-dashes, True → the bare flag of
// an option that takes no value (False and None: left out), a list or tuple → its items joined
// by commas (or repeated as separate options for a name in `repeated`), numbers as Python
// prints them (which reads back exactly), paths (os.PathLike) as the file system names them;
// progress=True shows the command's progress on stderr, which is --quiet otherwise.
// TypeError naming the keyword for a name in `refused` (and quiet=), saying why (`why`), and
// for a value of the wrong type: progress= and the flags want True or False, the others a
// number, a str, a path or a list of them (a bool is not a value).
std::vector<std::string> keyword_options(const pybind11::kwargs& kwargs,
                                         const std::vector<std::string>& refused,
                                         const std::string& why,
                                         const std::vector<std::string>& repeated = {});

// A path argument as the bytes the file system takes, as open() takes it: a str (encoded as
// os.fsencode does: a name os.listdir gave back finds its file), bytes or an os.PathLike.
// ValueError for an embedded NUL, TypeError naming `keyword` for another type.
std::string path_argument(const pybind11::handle& value, const char* keyword);

// Text from C++ (a message may quote a file or variant name in any bytes) as a str: UTF-8, the
// bytes that are not shown as \xNN. A path as os.fsdecode gives it (surrogate escapes), so that
// it opens the same file again.
pybind11::str message_text(const std::string& text);
pybind11::str path_text(const std::string& path);

void add_studies(pybind11::module_& m);

}  // namespace dacrt::python
