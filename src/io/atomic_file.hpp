#pragma once
// Write-to-temporary-then-rename: readers (ParaView, plotting scripts, a later restart) see either the
// old complete file or the new complete file, never a half-written one, even if the run is killed.
// The temporary lives in the same directory as the target, because rename(2) is only atomic within one
// file system. The temporary is a new regular file (O_CREAT | O_EXCL | O_NOFOLLOW: never an existing file
// or a symbolic link's target), and rename replaces whatever is at the target's name (a link included)
// without writing to it: nothing is ever written through a link or into another name of a hard-linked file.
#include <memory>
#include <ostream>
#include <string>

namespace fibrane::io {

// Replaces `path` with `content` atomically. Throws std::runtime_error on I/O failure.
void write_file_atomic(const std::string& path, const std::string& content);

// Stream-like writer: `AtomicFileWriter out(path); out << ...; out.commit();`. Until commit() the
// target is untouched; destroying an uncommitted writer removes the temporary.
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(std::string path);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  template <typename T>
  AtomicFileWriter& operator<<(const T& value) {
    stream_ << value;
    return *this;
  }
  std::ostream& stream() { return stream_; }
  void write(const char* data, std::size_t size) { stream_.write(data, static_cast<std::streamsize>(size)); }

  // Flushes, checks for write errors and renames the temporary onto the target.
  void commit();

  const std::string& path() const { return path_; }
  const std::string& temporary_path() const { return temporary_path_; }

  class Buffer;  // a stream buffer over the temporary's file descriptor

 private:
  std::string path_;
  std::string temporary_path_;
  std::unique_ptr<Buffer> buffer_;
  std::ostream stream_;
  bool committed_ = false;
};

}  // namespace fibrane::io
