// Error: the one exception type for bad input and failed I/O. Its message is a complete,
// single-line sentence for the user that names the file and the element at fault; the CLI prints it
// and exits 1.
#pragma once

#include <stdexcept>
#include <string>

namespace dacrt {

struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A mistake in how a command or function was called (an unknown option, a value out of range):
// the CLI prints it with a pointer to the command's --help and exits 2, Python raises ValueError.
// Not an Error: nothing about the input is wrong.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// An Error in what the caller asked rather than in the input (a camera override that cannot make
// a view): the CLI reports it as a usage mistake, exit 2.
struct SettingError : Error {
  using Error::Error;
};

// A library's message (OpenEXR, OpenColorIO, Embree, the OS) made fit for an Error: line breaks
// become spaces and trailing blanks go.
inline std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

}  // namespace dacrt
