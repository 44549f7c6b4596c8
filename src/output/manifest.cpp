#include "output/manifest.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "common/error.hpp"
#include "io/atomic_file.hpp"
#include "output/directory_lock.hpp"

namespace fibrane::output {

namespace {

constexpr const char* kHeader = "# fibrane manifest 1: the files this run wrote in its output directory";
constexpr std::size_t kMaxManifestBytes = std::size_t{256} << 20;

std::string manifest_path(const std::string& directory) {
  return (std::filesystem::path(directory) / kManifestFile).string();
}

bool valid_name(const std::string& name) {
  return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos &&
         name.find('\0') == std::string::npos && name != kManifestFile && name != kLockFile;
}

// The folder ("", "vtk" or "interaction") and the file name of a listed path; false if it is not one.
bool split_listed(const std::string& path, std::string& folder, std::string& name) {
  const std::size_t slash = path.find('/');
  folder = slash == std::string::npos ? "" : path.substr(0, slash);
  name = slash == std::string::npos ? path : path.substr(slash + 1);
  return (folder.empty() || folder == "vtk" || folder == "interaction") && valid_name(name);
}

// `name` is `<listed>.tmp.<digits>.<digits>` (io/atomic_file.cpp) for a name in `listed`.
bool is_temporary_of(const std::string& name, const std::set<std::string>& listed) {
  const std::size_t at = name.rfind(".tmp.");
  if (at == std::string::npos || !listed.count(name.substr(0, at))) return false;
  const std::string rest = name.substr(at + 5);
  const std::size_t dot = rest.find('.');
  auto digits = [](const std::string& s) { return !s.empty() && s.find_first_not_of("0123456789") == std::string::npos; };
  return dot != std::string::npos && digits(rest.substr(0, dot)) && digits(rest.substr(dot + 1));
}

void write_all(int fd, const std::string& text, const std::string& path) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw std::runtime_error(fmt::format("{}: write failed: {}", path, std::strerror(errno)));
    done += static_cast<std::size_t>(n);
  }
}

}  // namespace

std::vector<std::string> read_manifest(const std::string& directory) {
  const std::string path = manifest_path(directory);
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0 && errno == ENOENT) return {};
  if (fd < 0)
    throw InputError(fmt::format("{}: cannot read the manifest of the earlier run: {}", path,
                                 errno == ELOOP ? "it is a symbolic link" : std::strerror(errno)));
  struct stat st {};
  std::string text;
  const bool regular = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode);
  if (regular && static_cast<std::size_t>(st.st_size) <= kMaxManifestBytes) {
    text.resize(static_cast<std::size_t>(st.st_size));
    const ssize_t n = ::pread(fd, text.data(), text.size(), 0);
    text.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
  }
  ::close(fd);
  if (!regular) throw InputError(path + ": the manifest of the earlier run is not a regular file");
  if (static_cast<std::size_t>(st.st_size) > kMaxManifestBytes)
    throw InputError(path + ": the manifest of the earlier run is larger than 256 MiB");
  std::vector<std::string> listed;
  std::size_t start = 0;
  // Complete lines only: a killed append leaves at most a partial last line, whose file was never created.
  for (int line = 1;; ++line) {
    const std::size_t end = text.find('\n', start);
    if (end == std::string::npos) break;
    const std::string entry = text.substr(start, end - start);
    start = end + 1;
    std::string folder, name;
    if (line == 1) {
      if (entry.rfind("# fibrane manifest 1", 0) != 0)
        throw InputError(path + ": line 1: not a fibrane manifest (expected '# fibrane manifest 1'); remove the file "
                                "if it is not one");
    } else if (!split_listed(entry, folder, name)) {
      throw InputError(fmt::format("{}: line {}: '{}' is not a file a run writes (a file name, vtk/<name> or "
                                   "interaction/<name>); remove the manifest if it was edited",
                                   path, line, entry));
    } else {
      listed.push_back(entry);
    }
  }
  return listed;
}

void remove_listed_files(const std::string& directory, const std::vector<std::string>& listed,
                         bool temporaries_only) {
  std::map<std::string, std::set<std::string>> by_folder;
  for (const auto& entry : listed) {
    std::string folder, name;
    if (split_listed(entry, folder, name)) by_folder[folder].insert(name);
  }
  const int dir_fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (dir_fd < 0) return;
  for (const auto& [folder, names] : by_folder) {
    const int fd = folder.empty() ? ::dup(dir_fd)
                                  : ::openat(dir_fd, folder.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) continue;  // no such folder, or not a real one: nothing of the run in it
    auto remove_regular = [&](const std::string& name) {
      struct stat st {};
      if (::fstatat(fd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISREG(st.st_mode))
        ::unlinkat(fd, name.c_str(), 0);
    };
    if (!temporaries_only)
      for (const auto& name : names) remove_regular(name);
    DIR* d = ::fdopendir(::dup(fd));
    std::vector<std::string> temporaries;
    if (d) {
      while (const dirent* e = ::readdir(d))
        if (is_temporary_of(e->d_name, names)) temporaries.emplace_back(e->d_name);
      ::closedir(d);
    }
    for (const auto& name : temporaries) remove_regular(name);
    ::close(fd);
  }
  ::close(dir_fd);
}

Manifest::Manifest(std::string directory, const std::vector<std::string>& listed)
    : path_(manifest_path(directory)), files_(listed.begin(), listed.end()) {
  std::string text = std::string(kHeader) + "\n";
  for (const auto& f : files_) text += f + "\n";
  io::write_file_atomic(path_, text);
  fd_ = ::open(path_.c_str(), O_WRONLY | O_APPEND | O_NOFOLLOW | O_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error(fmt::format("{}: cannot open: {}", path_, std::strerror(errno)));
}

Manifest::~Manifest() {
  if (fd_ >= 0) ::close(fd_);
}

void Manifest::add(const std::string& relative_path) {
  if (files_.insert(relative_path).second) write_all(fd_, relative_path + "\n", path_);
}

}  // namespace fibrane::output
