#pragma once
// How much memory this process has and may still take: the machine's (/proc/meminfo), bounded by the
// control group it runs in (a batch system's job limit: cgroup v2 memory.max, or v1
// memory.limit_in_bytes), plus the free memory its own allocator already holds. The case reader sizes a
// model against memory_limit(); the direct solvers bound each factorisation by available_memory().
#include <cstddef>
#include <cstdint>
#include <vector>

namespace fibrane {

// MemTotal of /proc/meminfo, or the control group's limit where that is lower; bytes, 0 when neither
// can be read.
std::uint64_t memory_limit();

// Bytes this process can still allocate before the system (or its control group) runs out:
// MemAvailable, or the control group's limit less its usage where that is lower, plus the bytes freed
// inside this process that its allocator keeps for reuse (mallinfo2's fordblks: fibrane keeps freed work
// arrays, run/process_environment.cpp). 0 when /proc/meminfo cannot be read.
std::uint64_t available_memory();

// Hands the whole pages inside [data, data + bytes) back to the system (madvise MADV_DONTNEED), for a
// large buffer that is about to be freed: its contents are lost (they read as zeros until written), and
// its place stays the allocator's. fibrane's allocator keeps freed memory resident
// (run/process_environment.cpp), so a buffer replaced by a larger one would otherwise stay in the resident
// set beside its successor. The first and last 4 KiB are left alone (the allocator's own records).
void release_pages(const void* data, std::size_t bytes);

// Empties v and frees its storage, its pages handed back first (release_pages).
template <class T>
void release_storage(std::vector<T>& v) {
  release_pages(v.data(), sizeof(T) * v.capacity());
  std::vector<T>().swap(v);
}

}  // namespace fibrane
