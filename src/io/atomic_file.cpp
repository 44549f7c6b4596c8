#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <streambuf>

namespace fibrane::io {

namespace {

// Unique per process and per writer, so concurrent writers (threads or processes) never share a
// temporary file.
std::string make_temporary_path(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  return fmt::format("{}.tmp.{}.{}", path, static_cast<long>(::getpid()), counter++);
}

}  // namespace

// Buffers the stream's characters and writes them to the file descriptor; remembers the first error.
class AtomicFileWriter::Buffer : public std::streambuf {
 public:
  explicit Buffer(int fd) : fd_(fd) { setp(data_, data_ + sizeof data_); }
  ~Buffer() override { close(); }
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  // Writes what is buffered and closes the descriptor; the errno of the first failure, or 0.
  int close() {
    if (fd_ >= 0) {
      drain();
      if (::close(fd_) != 0 && error_ == 0) error_ = errno;
      fd_ = -1;
    }
    return error_;
  }

 protected:
  int_type overflow(int_type c) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  bool drain() {
    const char* p = pbase();
    while (error_ == 0 && p < pptr()) {
      const ssize_t n = ::write(fd_, p, static_cast<std::size_t>(pptr() - p));
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) error_ = errno;
      else p += n;
    }
    setp(data_, data_ + sizeof data_);
    return error_ == 0;
  }

  int fd_;
  int error_ = 0;
  char data_[1 << 16];
};

AtomicFileWriter::AtomicFileWriter(std::string path)
    : path_(std::move(path)), temporary_path_(make_temporary_path(path_)), stream_(nullptr) {
  const int fd = ::open(temporary_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) {
    throw std::runtime_error(
        fmt::format("{}: cannot create temporary file: {}", temporary_path_, std::strerror(errno)));
  }
  buffer_ = std::make_unique<Buffer>(fd);
  stream_.rdbuf(buffer_.get());
}

AtomicFileWriter::~AtomicFileWriter() {
  if (!committed_) {
    buffer_->close();
    std::remove(temporary_path_.c_str());
  }
}

void AtomicFileWriter::commit() {
  if (committed_) throw std::logic_error(path_ + ": AtomicFileWriter committed twice");
  // The stream keeps no error code: errno is that of the write(2) that failed (a failed stream writes no more).
  int error = stream_.fail() ? errno : 0;
  stream_.flush();
  if (!error && stream_.fail()) error = errno;
  const int close_error = buffer_->close();
  if (!error) error = close_error;
  if (error != 0 || stream_.fail()) {
    std::remove(temporary_path_.c_str());
    throw std::runtime_error(fmt::format("{}: write failed: {}", temporary_path_,
                                         error != 0 ? std::strerror(error) : "stream error"));
  }
  if (std::rename(temporary_path_.c_str(), path_.c_str()) != 0) {
    const int rename_error = errno;
    std::remove(temporary_path_.c_str());
    throw std::runtime_error(
        fmt::format("{}: cannot rename into place: {}", path_, std::strerror(rename_error)));
  }
  committed_ = true;
}

void write_file_atomic(const std::string& path, const std::string& content) {
  AtomicFileWriter out(path);
  out.write(content.data(), content.size());
  out.commit();
}

}  // namespace fibrane::io
