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

// Whether memory this process frees should go back to the system now instead of staying in its allocator
// for reuse: true where the system (or the control group) has less memory available than the process would
// then hold freed (mallinfo2's fordblks plus `about_to_free` bytes), or where /proc/meminfo cannot be read.
// Memory handed back is not free to take again: the kernel zeroes every page at its next touch, and on a
// virtual machine whose host reclaims the guest's free pages that costs seconds per GB
// (bench_fresh_memory; docs/performance.md, "Memory handed back"). Kept, a freed buffer is reused by the
// next one that fits its place; one that does not fit takes fresh memory beside it, which the rule leaves
// room for: the system keeps at least as much available as the process holds freed.
bool hand_back_needed(std::size_t about_to_free = 0);

// Hands the whole pages inside [data, data + bytes) back to the system (madvise MADV_DONTNEED): their
// contents are lost (they read as zeros until written), and the buffer stays allocated. The first and last
// 4 KiB are left alone (the allocator's own records next to them).
void hand_back_pages(const void* data, std::size_t bytes);

// hand_back_pages where hand_back_needed(bytes) says so, for a large buffer that is about to be freed.
// fibrane's allocator keeps freed memory resident (run/process_environment.cpp), so a buffer replaced by a
// larger one would otherwise stay in the resident set beside its successor.
void release_pages(const void* data, std::size_t bytes);

// Empties v and frees its storage, its pages handed back first where memory is short (release_pages).
template <class T>
void release_storage(std::vector<T>& v) {
  release_pages(v.data(), sizeof(T) * v.capacity());
  std::vector<T>().swap(v);
}

}  // namespace fibrane
