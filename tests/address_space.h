// A test's address space held to a little more than it uses (RLIMIT_AS, which
// dacrt::available_memory() reads), so that a bound on memory trips after little work.
#pragma once

#include <sys/resource.h>

#include <cstdint>
#include <fstream>
#include <string>

namespace dacrt::test {

// While it lives, the address space may grow by about `room` bytes only; ok() says whether the
// limit could be set (the current size is read from /proc/self/status).
class AddressSpaceRoom {
 public:
  explicit AddressSpaceRoom(uint64_t room) {
    getrlimit(RLIMIT_AS, &saved_);
    std::ifstream status("/proc/self/status");
    std::string line;
    uint64_t vm_kib = 0;
    while (std::getline(status, line))
      if (line.rfind("VmSize:", 0) == 0) vm_kib = std::stoull(line.substr(7));
    rlimit lower = saved_;
    lower.rlim_cur = vm_kib * 1024 + room;
    ok_ = vm_kib > 0 && (saved_.rlim_max == RLIM_INFINITY || lower.rlim_cur <= saved_.rlim_max) &&
          setrlimit(RLIMIT_AS, &lower) == 0;
  }
  ~AddressSpaceRoom() { setrlimit(RLIMIT_AS, &saved_); }
  AddressSpaceRoom(const AddressSpaceRoom&) = delete;
  AddressSpaceRoom& operator=(const AddressSpaceRoom&) = delete;
  bool ok() const { return ok_; }

 private:
  rlimit saved_{};
  bool ok_ = false;
};

}  // namespace dacrt::test
