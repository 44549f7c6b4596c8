#pragma once
// One run per output directory: a run holds an exclusive flock(2) on `<directory>/.fibrane.lock` from
// before its first write until it exits. The file names the holder (pid, host, start time) for the
// error a second run gets. The lock goes with the file descriptor, so a killed run leaves the file but
// no lock, and the next run takes it.
#include <string>

namespace fibrane::output {

// The name of the lock file in a run's output directory.
inline constexpr const char* kLockFile = ".fibrane.lock";

// An exclusive lock on an output directory, held for the object's lifetime (movable, not copyable).
class DirectoryLock {
 public:
  DirectoryLock() = default;
  // Locks `directory`, creating it (and its parents) first if `create` is true; with `create` false a
  // missing directory is not locked (there is nothing in it to protect). InputError, exit code 2, if
  // another process holds the lock (naming the directory and that run's pid and host), if the directory
  // or its lock file is a symbolic link, or if the lock file cannot be created. On a file system without
  // locks the run goes on unlocked (warning()).
  DirectoryLock(const std::string& directory, bool create);
  ~DirectoryLock();
  DirectoryLock(DirectoryLock&& other) noexcept;
  DirectoryLock& operator=(DirectoryLock&& other) noexcept;
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;

  // Not empty if the directory's file system does not support flock (some network and parallel file
  // systems): the run goes on unlocked, and this says so.
  const std::string& warning() const { return warning_; }
  // Undoes what locking wrote, for a run refused before it wrote anything else: removes the lock file
  // and the directories locking created, where they did not exist before; releases the lock.
  void abandon();

 private:
  void release();

  int fd_ = -1;
  std::string directory_;
  std::string created_from_;  // the topmost directory locking created ("" if none)
  bool created_file_ = false;
  std::string warning_;
};

}  // namespace fibrane::output
