#include "output/directory_lock.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <utility>

#include "common/error.hpp"

namespace fibrane::output {

namespace {

namespace fs = std::filesystem;

std::string lock_path(const std::string& directory) { return (fs::path(directory) / kLockFile).string(); }

// "pid 1234 on host node7, started 2026-01-02T03:04:05Z" from a lock file's lines.
std::string describe_holder(int fd) {
  char buffer[1024];
  const ssize_t n = ::pread(fd, buffer, sizeof buffer - 1, 0);
  const std::string text(buffer, n > 0 ? static_cast<std::size_t>(n) : 0);
  auto field = [&](const std::string& key) {
    const std::size_t at = text.find(key + " ");
    if (at == std::string::npos) return std::string("?");
    const std::size_t start = at + key.size() + 1;
    return text.substr(start, text.find('\n', start) - start);
  };
  if (text.empty()) return "it has not written its pid yet";
  return fmt::format("pid {} on host {}, started {}", field("pid"), field("host"), field("started"));
}

std::string holder_text() {
  char host[256] = "?";
  if (::gethostname(host, sizeof host - 1) != 0) std::strcpy(host, "?");
  host[sizeof host - 1] = '\0';
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  char started[32] = "?";
  if (::gmtime_r(&now, &utc)) std::strftime(started, sizeof started, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return fmt::format("pid {}\nhost {}\nstarted {}\n", static_cast<long>(::getpid()), host, started);
}

// The topmost of `directory` and its ancestors that does not exist ("" if it exists).
std::string topmost_missing(const std::string& directory) {
  std::error_code ec;
  fs::path p = fs::absolute(directory, ec), top;
  while (!p.empty() && !fs::exists(fs::symlink_status(p, ec))) {
    top = p;
    if (p.parent_path() == p) break;
    p = p.parent_path();
  }
  return top.string();
}

}  // namespace

DirectoryLock::DirectoryLock(const std::string& directory, bool create) : directory_(directory) {
  const std::string where = "output directory '" + directory + "'";
  struct stat st {};
  if (::lstat(directory.c_str(), &st) != 0) {
    if (errno != ENOENT) throw InputError(fmt::format("{}: {}", where, std::strerror(errno)));
    if (!create) return;
    created_from_ = topmost_missing(directory);
    std::error_code ec;
    fs::create_directories(directory, ec);
    if (ec) throw InputError(fmt::format("{}: cannot create it: {}", where, ec.message()));
  } else if (S_ISLNK(st.st_mode)) {
    throw InputError(where + ": is a symbolic link; fibrane writes only into a real directory (name the directory "
                             "the link points to, or another one)");
  } else if (!S_ISDIR(st.st_mode)) {
    throw InputError(where + ": exists and is not a directory");
  }
  const int dir_fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (dir_fd < 0) throw InputError(fmt::format("{}: cannot open it: {}", where, std::strerror(errno)));
  const std::string path = lock_path(directory);
  // A lock file removed by abandon() between our open and our flock is not the directory's lock: try again
  // with the file now at the name.
  for (int attempt = 0; attempt < 100 && fd_ < 0; ++attempt) {
    bool created = true;
    int fd = ::openat(dir_fd, kLockFile, O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0 && errno == EEXIST) {
      created = false;
      fd = ::openat(dir_fd, kLockFile, O_RDWR | O_NOFOLLOW | O_CLOEXEC);
    }
    if (fd < 0 && errno == ENOENT) continue;
    const int error = errno;
    struct stat file {};
    if (fd < 0 || ::fstat(fd, &file) != 0 || !S_ISREG(file.st_mode)) {
      if (fd >= 0) ::close(fd);
      ::close(dir_fd);
      throw InputError(fmt::format("{}: cannot use it as the lock file: {}", path,
                                   fd < 0 && error == ELOOP ? "it is a symbolic link"
                                   : fd < 0                 ? std::strerror(error)
                                                            : "it is not a regular file"));
    }
    const int lock_error = ::flock(fd, LOCK_EX | LOCK_NB) == 0 ? 0 : errno;
    if (lock_error == ENOLCK || lock_error == ENOSYS || lock_error == EOPNOTSUPP) {
      warning_ = fmt::format("{}: the file system does not support locks ({}): nothing stops a second run from "
                             "writing into this directory at the same time",
                             path, std::strerror(lock_error));
    } else if (lock_error != 0) {
      const std::string holder = describe_holder(fd);
      ::close(fd);
      ::close(dir_fd);
      if (lock_error == EWOULDBLOCK)
        throw InputError(fmt::format("{}: another fibrane run is writing into this directory ({}; lock file {}); "
                                     "wait for it to end, or choose another output directory",
                                     where, holder, path));
      throw InputError(fmt::format("{}: cannot lock it: {}", path, std::strerror(lock_error)));
    }
    struct stat named {};
    if (::fstatat(dir_fd, kLockFile, &named, AT_SYMLINK_NOFOLLOW) != 0 || named.st_ino != file.st_ino ||
        named.st_dev != file.st_dev) {
      ::close(fd);
      continue;
    }
    fd_ = fd;
    created_file_ = created;
  }
  ::close(dir_fd);
  if (fd_ < 0) throw InputError(path + ": cannot lock it: the file keeps being replaced");
  const std::string text = holder_text();
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, text.data(), text.size(), 0) != static_cast<ssize_t>(text.size())) {
    const int error = errno;
    abandon();
    throw std::runtime_error(fmt::format("{}: write failed: {}", path, std::strerror(error)));
  }
}

DirectoryLock::~DirectoryLock() { release(); }

DirectoryLock::DirectoryLock(DirectoryLock&& other) noexcept { *this = std::move(other); }

DirectoryLock& DirectoryLock::operator=(DirectoryLock&& other) noexcept {
  if (this != &other) {
    release();
    fd_ = std::exchange(other.fd_, -1);
    directory_ = std::move(other.directory_);
    created_from_ = std::move(other.created_from_);
    created_file_ = other.created_file_;
    warning_ = std::move(other.warning_);
  }
  return *this;
}

void DirectoryLock::release() {
  if (fd_ >= 0) ::close(fd_);  // closing the last descriptor releases the flock
  fd_ = -1;
}

void DirectoryLock::abandon() {
  if (fd_ < 0) return;
  if (created_file_) ::unlink(lock_path(directory_).c_str());  // still locked: no other run holds this file
  release();
  if (created_from_.empty()) return;
  std::error_code ec;
  for (fs::path p = fs::absolute(directory_, ec); !p.empty(); p = p.parent_path()) {
    if (::rmdir(p.c_str()) != 0 || p == created_from_ || p.parent_path() == p) break;
  }
}

}  // namespace fibrane::output
