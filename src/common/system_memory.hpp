#pragma once
// How much memory this process has and may still take: the machine's (/proc/meminfo), bounded by the
// control group it runs in (a batch system's job limit: cgroup v2 memory.max, or v1
// memory.limit_in_bytes), plus the free memory its own allocator already holds. The case reader sizes a
// model against memory_limit(); the direct solvers bound each factorisation by available_memory().
#include <cstdint>

namespace fibrane {

// MemTotal of /proc/meminfo, or the control group's limit where that is lower; bytes, 0 when neither
// can be read.
std::uint64_t memory_limit();

// Bytes this process can still allocate before the system (or its control group) runs out:
// MemAvailable, or the control group's limit less its usage where that is lower, plus the bytes freed
// inside this process that its allocator keeps for reuse (mallinfo2's fordblks: fibrane keeps freed work
// arrays, app/openmp_environment.cpp). 0 when /proc/meminfo cannot be read.
std::uint64_t available_memory();

}  // namespace fibrane
