// How much memory this process may still take: the least of the system's available memory
// (/proc/meminfo MemAvailable), the room left under its cgroup's limit (cgroup v2 memory.max) and
// its address-space limit (RLIMIT_AS). Used to refuse, before it starts, work that cannot fit.
#pragma once

#include <cstdint>
#include <string>

namespace dacrt {

// Bytes; UINT64_MAX when nothing can be read (no /proc, no limits).
uint64_t available_memory();

// "1.5 GiB", "320 MiB", "12 KiB", "100 B": sizes for messages.
std::string format_bytes(uint64_t bytes);

}  // namespace dacrt
