#include "studies.h"

#include <pybind11/stl.h>
#include <stdlib.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "studies/converge.h"
#include "bench/args.h"
#include "bench/command.h"
#include "bench/report.h"
#include "dacrt/render/request.h"
#include "dacrt/util/error.h"
#include "dacrt/util/text.h"
#include "interruptible.h"

namespace py = pybind11;
namespace fs = std::filesystem;

namespace dacrt::python {

std::string path_argument(const py::handle& value, const char* keyword) {
  PyObject* encoded = nullptr;
  if (!PyUnicode_FSConverter(value.ptr(), &encoded)) {
    py::error_already_set error;
    if (error.matches(PyExc_TypeError))
      throw py::type_error(std::string(keyword) + "= wants a path (str, bytes or os.PathLike), not " +
                           std::string(py::str(value.get_type().attr("__name__"))));
    throw error;  // ValueError: embedded null byte
  }
  const py::bytes bytes = py::reinterpret_steal<py::bytes>(encoded);
  return std::string(bytes);
}

py::str message_text(const std::string& text) {
  PyObject* s = PyUnicode_DecodeUTF8(text.data(), Py_ssize_t(text.size()), "backslashreplace");
  if (!s) throw py::error_already_set();
  return py::reinterpret_steal<py::str>(s);
}

py::str path_text(const std::string& path) {
  PyObject* s = PyUnicode_DecodeFSDefaultAndSize(path.data(), Py_ssize_t(path.size()));
  if (!s) throw py::error_already_set();
  return py::reinterpret_steal<py::str>(s);
}

std::vector<std::string> keyword_options(const py::kwargs& kwargs,
                                         const std::vector<std::string>& refused,
                                         const std::string& why,
                                         const std::vector<std::string>& repeated) {
  // The commands' options that take no value (render, bench and converge).
  static const std::vector<std::string> flags = {"keep_sums",   "resume",   "tmax_at_hit",
                                                 "no_reference", "noise",   "no_plot"};
  std::vector<std::string> args;
  bool progress = false;
  auto listed = [](const std::vector<std::string>& names, const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
  };
  auto type_name = [](py::handle v) {
    return std::string(py::str(v.get_type().attr("__name__")));
  };
  for (const auto& [key, value] : kwargs) {
    const std::string name = py::cast<std::string>(key);
    if (name == "quiet") throw py::type_error("no quiet= here: progress=True shows the progress");
    if (listed(refused, name)) throw py::type_error("no " + name + "= here (" + why + ")");
    const bool flag_option = name == "progress" || listed(flags, name);
    if (flag_option && !value.is_none() && !py::isinstance<py::bool_>(value))
      throw py::type_error(name + "= wants True or False, not " + type_name(value));
    if (name == "progress") {
      progress = !value.is_none() && py::cast<bool>(value);
      continue;
    }
    std::string flag = "--" + name;
    std::replace(flag.begin(), flag.end(), '_', '-');
    if (value.is_none()) continue;
    if (flag_option) {
      if (py::cast<bool>(value)) args.push_back(flag);
      continue;
    }
    // A value: a number, a str or a path, or (for a list option) a list or tuple of them.
    auto text = [&](py::handle v) -> std::string {
      if (py::isinstance<py::bool_>(v))
        throw py::type_error(name + "= wants a value, not " + std::string(py::str(v)));
      if (py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v))
        return std::string(py::str(v));
      if (py::isinstance<py::str>(v) || py::isinstance<py::bytes>(v) ||
          py::hasattr(v, "__fspath__"))
        return path_argument(v, name.c_str());
      throw py::type_error(name + "= wants a number, a str or a path" +
                           (listed(repeated, name) ? std::string(", or a list of them") : "") +
                           ", not " + type_name(v));
    };
    const bool sequence = py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value);
    if (sequence && listed(repeated, name)) {
      for (const py::handle item : value) args.push_back(flag), args.push_back(text(item));
      continue;
    }
    std::string joined;
    if (sequence)
      for (const py::handle item : value) joined += (joined.empty() ? "" : ",") + text(item);
    else
      joined = text(value);
    args.push_back(flag);
    args.push_back(joined);
  }
  if (!progress) args.push_back("--quiet");
  return args;
}

namespace {

// The JSON of `dacrt bench --json` as Python data, and the warnings.
py::object bench(const py::object& scene_path, const py::kwargs& kwargs) {
  std::vector<std::string> args = {path_argument(scene_path, "scene")};
  for (std::string& a : keyword_options(kwargs, {"json", "report", "help"},
                                        "bench() returns its results: use the CLI for files",
                                        {"backend_option"}))
    args.push_back(std::move(a));
  bench::BenchArgs parsed = bench::parse_bench_args(args);
  std::vector<std::string> said;
  parsed.warnings = &said;
  std::atomic<bool> stop{false};  // a bench is not stopped midway: Ctrl-C waits for its end
  const std::string text = run_interruptible(
      stop, [&] { return json_text(bench::to_json(bench::bench_report(parsed))); });
  py::list warnings;
  for (const std::string& w : said) warnings.append(message_text(w));
  return py::make_tuple(py::module_::import("json").attr("loads")(text), warnings);
}

// A directory of its own, removed with what it holds when the call ends.
struct TemporaryDirectory {
  fs::path path;
  TemporaryDirectory() {
    std::string pattern = (fs::temp_directory_path() / "dacrt-converge-XXXXXX").string();
    if (!::mkdtemp(pattern.data())) throw Error("cannot make a temporary directory");
    path = pattern;
  }
  ~TemporaryDirectory() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

// `dacrt converge` run in a temporary directory removed afterwards: (its convergence.csv's
// header, its rows as lists of text, its warnings and notes). Nothing goes to stdout. With
// reference= given, the reference the CLI would keep is not kept.
py::object converge(const py::object& scene_path, const py::kwargs& kwargs) {
  const TemporaryDirectory dir;
  std::vector<std::string> args = {path_argument(scene_path, "scene"), "-o", dir.path.string(),
                                   "--no-plot"};
  // A list for a repeatable option repeats it: --config, --target-error and the render options'.
  std::vector<std::string> repeated = {"config", "target_error"};
  for (const RenderOption& o : render_options())
    if (o.repeatable) repeated.push_back(o.python_keyword());
  for (std::string& a :
       keyword_options(kwargs, {"output", "o", "no_plot", "help"},
                       "converge() returns its points: use the CLI for files", repeated))
    args.push_back(std::move(a));
  std::atomic<bool> stop{false};  // converge stops on SIGINT itself, as the CLI does
  ConvergeSaid said;
  const int code = run_interruptible(stop, [&] { return converge_for_library(args, said); });
  if (code != 0) {
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
  }
  const py::module_ csv = py::module_::import("csv");
  const py::object file = py::module_::import("io").attr("open")(
      (dir.path / "convergence.csv").string(), "r", py::arg("newline") = "");
  const py::list rows = py::list(csv.attr("reader")(file));
  file.attr("close")();
  py::list warnings;
  for (const std::string& w : said.warnings) warnings.append(message_text(w));
  const py::object header = rows.empty() ? py::object(py::list()) : rows[0];
  return py::make_tuple(header, rows[py::slice(1, py::ssize_t(py::len(rows)), 1)], warnings);
}

}  // namespace

void add_studies(py::module_& m) {
  // The signatures and the documentation are the package's (python/dacrt/__init__.py).
  m.def("bench", &bench, py::arg("scene"));
  m.def("converge", &converge, py::arg("scene"));
}

}  // namespace dacrt::python
