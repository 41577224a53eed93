// The host program's own util/error.h, of the same name as dacrt's: dacrt's headers must never
// include it in place of theirs.
#pragma once

#ifndef HOST_INCLUDES_ITS_OWN
#error "a dacrt header included the host's util/error.h (an include without the dacrt/ prefix)"
#endif

#define HOST_UTIL_ERROR_H 1

namespace host {
struct Error {
  const char* what;
};
}  // namespace host
