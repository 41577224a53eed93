// Python's render() keywords: the render option table (render/request.h) read as typed keyword
// arguments. Each option Python takes is a keyword (its name without dashes, '-' as '_'; aovs=
// for --aov), of the option's type: a bool for a flag, an int, a number, a str, a path, three
// numbers for a point, two ints for a range, a str or a list of them for names; a list repeats a
// repeatable option. A keyword that is no option, or an option Python does not take (the files,
// the sequences), or a value of the wrong type is a TypeError; a bad value a ValueError (the
// option's own check, naming the keyword as `spp=`).
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "dacrt/render/request.h"

namespace dacrt::python {

// The request of render(path, **kwargs), checked (check_request); progress= shows the progress
// bar (r.quiet otherwise).
RenderRequest render_request(const std::string& path, const pybind11::kwargs& kwargs);

// Every keyword render() takes, for its signature and the test that ties them to the table.
std::vector<std::string> render_keywords();

// Each option Python takes, from the table, for the package's signatures and documentation
// (python/dacrt/__init__.py): (keyword, value type, repeatable, taken by converge(), help lines).
// The value type: flag, int, number, str, name_or_index, path, point, range, names or
// colour_or_file (render/request.h's OptionValue).
pybind11::list render_keyword_table();

}  // namespace dacrt::python
