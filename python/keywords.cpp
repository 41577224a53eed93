// render()'s keywords from the render option table (see keywords.h).
#include "keywords.h"

#include <algorithm>

#include "dacrt/util/text.h"
#include "studies.h"

namespace py = pybind11;

namespace dacrt::python {

namespace {

std::string type_name(py::handle v) { return std::string(py::str(v.get_type().attr("__name__"))); }

// How a message names an option: "--spp" → "spp=".
std::string keyword_of(std::string_view flag) {
  const RenderOption* o = find_render_option(flag);
  return (o ? o->python_keyword() : std::string(flag)) + "=";
}

bool is_bool(py::handle v) { return py::isinstance<py::bool_>(v); }
bool is_int(py::handle v) { return !is_bool(v) && PyIndex_Check(v.ptr()); }
bool is_number(py::handle v) {
  return !is_bool(v) && (PyIndex_Check(v.ptr()) || PyFloat_Check(v.ptr()) ||
                         (PyNumber_Check(v.ptr()) && !py::isinstance<py::str>(v)));
}
bool is_sequence(py::handle v) {
  return PySequence_Check(v.ptr()) && !py::isinstance<py::str>(v) && !py::isinstance<py::bytes>(v);
}

// A number as the CLI's parser reads it back exactly: an int's digits, a float's repr.
std::string number_text(py::handle v) {
  if (PyIndex_Check(v.ptr())) return std::string(py::str(py::reinterpret_steal<py::object>(PyNumber_Index(v.ptr()))));
  return std::string(py::repr(py::float_(py::reinterpret_borrow<py::object>(v))));
}

// `count` numbers joined by `sep`, or TypeError naming the keyword.
std::string numbers_text(const std::string& key, py::handle v, size_t count, const char* sep,
                         bool ints, const char* what) {
  std::string out;
  if (is_sequence(v)) {
    const py::sequence seq = py::reinterpret_borrow<py::sequence>(v);
    bool ok = py::len(seq) == count;
    for (size_t i = 0; ok && i < count; ++i) ok = ints ? is_int(seq[i]) : is_number(seq[i]);
    if (ok) {
      for (size_t i = 0; i < count; ++i) out += (i ? sep : "") + number_text(seq[i]);
      return out;
    }
  }
  throw py::type_error(key + "= wants " + what + ", not " +
                       (is_sequence(v) ? std::string(py::repr(v)) : type_name(v)));
}

// One value of option `o` as its command-line text; TypeError for a value of the wrong type.
std::string value_text(const RenderOption& o, const std::string& key, py::handle v) {
  using V = OptionValue;
  switch (o.value) {
    case V::none:
      return "";
    case V::integer:
      if (is_int(v)) return number_text(v);
      throw py::type_error(key + "= wants an int, not " + type_name(v));
    case V::number:
      if (is_number(v)) return number_text(v);
      throw py::type_error(key + "= wants a number, not " + type_name(v));
    case V::text:
      if (py::isinstance<py::str>(v) || py::isinstance<py::bytes>(v))
        return path_argument(v, key.c_str());
      throw py::type_error(key + "= wants a str, not " + type_name(v));
    case V::name_or_index:
      if (is_int(v)) return number_text(v);
      if (py::isinstance<py::str>(v) || py::isinstance<py::bytes>(v))
        return path_argument(v, key.c_str());
      throw py::type_error(key + "= wants a name or an index, not " + type_name(v));
    case V::path:
      return path_argument(v, key.c_str());
    case V::point:
      return numbers_text(key, v, 3, ",", false, "three numbers (x, y, z)");
    case V::range:
      return numbers_text(key, v, 2, ":", true, "two ints (first, last)");
    case V::names: {
      if (py::isinstance<py::str>(v) || py::isinstance<py::bytes>(v))
        return path_argument(v, key.c_str());
      if (!is_sequence(v)) throw py::type_error(key + "= wants a str or a list of str, not " + type_name(v));
      std::string joined;
      for (const py::handle item : v) {
        if (!py::isinstance<py::str>(item) && !py::isinstance<py::bytes>(item))
          throw py::type_error(key + "= wants a str or a list of str, not a list holding " +
                               type_name(item));
        joined += (joined.empty() ? "" : ",") + path_argument(item, key.c_str());
      }
      return joined;
    }
    case V::colour_or_file:
      if (is_sequence(v)) return numbers_text(key, v, 3, ",", false, "three numbers (r, g, b) or a path");
      return path_argument(v, key.c_str());
  }
  return "";
}

// The option whose keyword is `key`, or nullptr.
const RenderOption* option_of(const std::string& key) {
  for (const RenderOption& o : render_options())
    if (o.python_keyword() == key) return &o;
  return nullptr;
}

// " (did you mean spp=?)" for a keyword near one render() takes, else "".
std::string suggestion(const std::string& key) {
  std::vector<std::string> known;
  for (const std::string& k : render_keywords()) known.push_back(k + "=");
  return did_you_mean(key + "=", known);
}

}  // namespace

std::vector<std::string> render_keywords() {
  std::vector<std::string> keys;
  for (const RenderOption& o : render_options())
    if (o.uses & use_python) keys.push_back(o.python_keyword());
  keys.push_back("progress");
  return keys;
}

py::list render_keyword_table() {
  using V = OptionValue;
  auto type = [](V v) -> const char* {
    switch (v) {
      case V::none: return "flag";
      case V::integer: return "int";
      case V::number: return "number";
      case V::text: return "str";
      case V::name_or_index: return "name_or_index";
      case V::path: return "path";
      case V::point: return "point";
      case V::range: return "range";
      case V::names: return "names";
      case V::colour_or_file: return "colour_or_file";
    }
    return "";
  };
  py::list table;
  for (const RenderOption& o : render_options())
    if (o.uses & use_python)
      table.append(py::make_tuple(o.python_keyword(), type(o.value), o.repeatable,
                                  (o.uses & use_converge) != 0, std::string(o.help)));
  return table;
}

RenderRequest render_request(const std::string& path, const py::kwargs& kwargs) {
  RenderRequest r;
  r.scene = path;
  bool progress = false;
  for (const auto& [k, value] : kwargs) {
    const std::string key = py::cast<std::string>(k);
    if (key == "progress") {
      if (!value.is_none() && !is_bool(value))
        throw py::type_error("progress= wants True or False, not " + type_name(value));
      progress = !value.is_none() && py::cast<bool>(value);
      continue;
    }
    if (key == "aov")  // (the CLI's repeated --aov: here one list, which also asks for them back)
      throw py::type_error("no aov= here: aovs=[...] renders the AOVs and returns them");
    if (key == "quiet") throw py::type_error("no quiet= here: progress=True shows the progress");
    const RenderOption* o = option_of(key);
    if (o && !(o->uses & use_python))
      throw py::type_error("no " + key + "= here (render() returns arrays: use the CLI for files " +
                           "and sequences; give load() a scene index)");
    if (!o)
      throw py::type_error("render() got an unexpected keyword argument '" + key + "'" +
                           suggestion(key));
    if (value.is_none()) continue;
    const std::string name = key + "=";
    if (o->value == OptionValue::none) {
      if (!is_bool(value))
        throw py::type_error(name + " wants True or False, not " + type_name(value));
      if (py::cast<bool>(value)) o->apply(r, "", name);
      continue;
    }
    if (is_bool(value))
      throw py::type_error(name + " wants a value, not " + std::string(py::str(value)));
    if (o->repeatable && (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value))) {
      for (const py::handle item : value) o->apply(r, value_text(*o, key, item), name);
      continue;
    }
    o->apply(r, value_text(*o, key, value), name);
  }
  r.quiet = !progress;
  check_request(r, keyword_of);
  return r;
}

}  // namespace dacrt::python
