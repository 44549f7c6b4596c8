#include "common/system_memory.hpp"

#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

namespace fibrane {
namespace {

// The value of `key` ("MemTotal:", "MemAvailable:") in /proc/meminfo, in bytes; 0 when absent.
std::uint64_t meminfo(const std::string& key) {
  std::ifstream in("/proc/meminfo");
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string name;
    std::uint64_t kib = 0;
    if (words >> name >> kib && name == key) return kib * 1024;
  }
  return 0;
}

// The first number in `path`; 0 when the file is missing or holds none ("max": no limit).
std::uint64_t number_in(const std::string& path) {
  std::ifstream in(path);
  std::uint64_t value = 0;
  return in >> value ? value : 0;
}

// This process's control group path for the memory controller (v1: "N:memory:/path"; v2: "0::/path").
std::string cgroup_path(bool v2) {
  std::ifstream in("/proc/self/cgroup");
  std::string line;
  while (std::getline(in, line)) {
    const auto first = line.find(':');
    const auto second = line.find(':', first + 1);
    if (first == std::string::npos || second == std::string::npos) continue;
    const std::string controllers = line.substr(first + 1, second - first - 1);
    if (v2 ? controllers.empty() : controllers == "memory") return line.substr(second + 1);
  }
  return {};
}

// The control group's memory limit and usage in bytes ({0, 0} without a limit). The group's own
// directory is looked for under the mount point and, inside a cgroup namespace, at the mount point.
struct GroupMemory {
  std::uint64_t limit = 0, usage = 0;
};
GroupMemory group_memory() {
  constexpr std::uint64_t kNoLimit = std::uint64_t{1} << 60;  // v1 writes ~2^63 for "no limit"
  for (const bool v2 : {true, false}) {
    const std::string root = v2 ? "/sys/fs/cgroup" : "/sys/fs/cgroup/memory";
    const std::string limit_file = v2 ? "memory.max" : "memory.limit_in_bytes";
    const std::string usage_file = v2 ? "memory.current" : "memory.usage_in_bytes";
    for (const std::string& dir : {root + cgroup_path(v2), root}) {
      const std::uint64_t limit = number_in(dir + "/" + limit_file);
      if (limit > 0 && limit < kNoLimit) return {limit, number_in(dir + "/" + usage_file)};
    }
  }
  return {};
}

}  // namespace

std::uint64_t memory_limit() {
  const std::uint64_t total = meminfo("MemTotal:");
  const GroupMemory group = group_memory();
  if (group.limit == 0) return total;
  return total == 0 ? group.limit : std::min(total, group.limit);
}

namespace {

// MemAvailable, or the control group's limit less its usage where that is lower; nullopt when
// /proc/meminfo cannot be read.
std::optional<std::uint64_t> system_available_memory() {
  const std::uint64_t available = meminfo("MemAvailable:");
  if (available == 0) return std::nullopt;
  const GroupMemory group = group_memory();
  if (group.limit == 0) return available;
  return std::min(available, group.limit > group.usage ? group.limit - group.usage : 0);
}

}  // namespace

std::uint64_t available_memory() {
  const auto available = system_available_memory();
  return available ? *available + mallinfo2().fordblks : 0;
}

bool hand_back_needed(std::size_t about_to_free) {
  const auto available = system_available_memory();
  return !available || *available < mallinfo2().fordblks + about_to_free;
}

void release_pages(const void* data, std::size_t bytes) {
  if (hand_back_needed(bytes)) hand_back_pages(data, bytes);
}

void hand_back_pages(const void* data, std::size_t bytes) {
  static const std::uintptr_t page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  const std::uintptr_t begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + 4096 + page - 1) / page * page;
  const std::uintptr_t last = bytes > 4096 ? (begin + bytes - 4096) / page * page : 0;
  if (data && last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_DONTNEED);
}

}  // namespace fibrane
