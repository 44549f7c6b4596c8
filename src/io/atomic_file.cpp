#include "io/atomic_file.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace fibrane::io {

namespace {

// Unique per process and per writer, so concurrent writers (threads or processes) never share a
// temporary file.
std::string make_temporary_path(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  return fmt::format("{}.tmp.{}.{}", path, static_cast<long>(::getpid()), counter++);
}

}  // namespace

AtomicFileWriter::AtomicFileWriter(std::string path)
    : path_(std::move(path)), temporary_path_(make_temporary_path(path_)) {
  stream_.open(temporary_path_, std::ios::binary | std::ios::trunc);
  if (!stream_) {
    throw std::runtime_error(
        fmt::format("{}: cannot create temporary file: {}", temporary_path_, std::strerror(errno)));
  }
}

AtomicFileWriter::~AtomicFileWriter() {
  if (!committed_) {
    stream_.close();
    std::remove(temporary_path_.c_str());
  }
}

void AtomicFileWriter::commit() {
  if (committed_) throw std::logic_error(path_ + ": AtomicFileWriter committed twice");
  // The stream keeps no error code: errno is that of the write(2) that failed (a failed stream writes no more).
  int error = stream_.fail() ? errno : 0;
  stream_.flush();
  if (!error && stream_.fail()) error = errno;
  stream_.close();
  if (!error && stream_.fail()) error = errno;
  if (stream_.fail()) {
    std::remove(temporary_path_.c_str());
    throw std::runtime_error(
        fmt::format("{}: write failed: {}", temporary_path_, error ? std::strerror(error) : "unknown error"));
  }
  if (std::rename(temporary_path_.c_str(), path_.c_str()) != 0) {
    const int error = errno;
    std::remove(temporary_path_.c_str());
    throw std::runtime_error(fmt::format("{}: cannot rename into place: {}", path_, std::strerror(error)));
  }
  committed_ = true;
}

void write_file_atomic(const std::string& path, const std::string& content) {
  AtomicFileWriter out(path);
  out.write(content.data(), content.size());
  out.commit();
}

}  // namespace fibrane::io
