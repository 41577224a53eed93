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

}  // namespace dacrt
