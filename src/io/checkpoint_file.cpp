#include "io/checkpoint_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <new>

#include <fmt/format.h>

#include "common/error.hpp"
#include "common/hash.hpp"
#include "io/atomic_file.hpp"

namespace fibrane::io {
namespace {

constexpr char kMagicPrefix[] = "FIBRANE-CHECKPOINT ";
constexpr char kMagic[] = "FIBRANE-CHECKPOINT 2\n";
constexpr char kEnd[] = "END-CKPT";
constexpr std::size_t kMagicSize = sizeof(kMagic) - 1, kTrailerSize = 16;  // end marker + checksum
constexpr std::size_t kSmallestEntry = 1 + 4 + 8;                            // kind, name length, count
constexpr std::uint8_t kDoubles = 0, kText = 1;

template <typename T>
void put(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

void put_name(std::string& out, std::uint8_t kind, const std::string& name, std::uint64_t count) {
  put(out, kind);
  put(out, static_cast<std::uint32_t>(name.size()));
  out += name;
  put(out, count);
}

// Sequential reader of the entries' bytes (the file without its trailer); every read past their end is
// a located InputError.
class Reader {
 public:
  Reader(const std::string& bytes, std::size_t end, const std::string& path) : bytes_(bytes), end_(end), path_(path) {}
  template <typename T>
  T get(const char* field) {
    T value;
    std::memcpy(&value, take(sizeof(T), field), sizeof(T));
    return value;
  }
  const char* take(std::uint64_t n, const char* field) {
    if (n > remaining())
      throw InputError(fmt::format("{}: the checkpoint file is damaged: {} at byte {} needs {} bytes, {} are left",
                                   path_, field, pos_, n, remaining()));
    const char* p = bytes_.data() + pos_;
    pos_ += static_cast<std::size_t>(n);
    return p;
  }
  std::size_t remaining() const { return end_ - pos_; }

 private:
  const std::string& bytes_;
  std::size_t end_, pos_ = kMagicSize;
  const std::string& path_;
};

// The magic line, the trailer and the checksum; InputError saying which is wrong.
void check_seal(const std::string& bytes, const std::string& path) {
  if (bytes.empty()) throw InputError(path + ": the checkpoint file is empty");
  if (bytes.compare(0, kMagicSize, kMagic) != 0) {
    if (bytes.compare(0, sizeof(kMagicPrefix) - 1, kMagicPrefix) == 0)
      throw InputError(path + ": a checkpoint of another format version (this fibrane reads version 2): start "
                              "the run anew");
    throw InputError(path + ": not a fibrane checkpoint file");
  }
  if (bytes.size() < kMagicSize + 8 + kTrailerSize ||
      bytes.compare(bytes.size() - kTrailerSize, 8, kEnd) != 0)
    throw InputError(fmt::format("{}: the checkpoint file is truncated or damaged: its {} bytes do not end with the "
                                 "end marker and the checksum",
                                 path, bytes.size()));
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
  const std::uint64_t computed = fnv1a64(bytes.data(), bytes.size() - 8);
  if (stored != computed)
    throw InputError(fmt::format("{}: the checkpoint file is damaged: its checksum ({:016x}) does not match its "
                                 "content ({:016x}); it was changed after fibrane wrote it",
                                 path, stored, computed));
}

}  // namespace

const std::vector<double>& CheckpointData::array(const std::string& name, const std::string& what) const {
  const auto it = arrays.find(name);
  if (it == arrays.end()) throw InputError(what + ": the checkpoint has no entry '" + name + "'");
  return it->second;
}

const std::string& CheckpointData::text(const std::string& name, const std::string& what) const {
  const auto it = texts.find(name);
  if (it == texts.end()) throw InputError(what + ": the checkpoint has no entry '" + name + "'");
  return it->second;
}

double CheckpointData::scalar(const std::string& name, const std::string& what) const {
  const auto& a = array(name, what);
  if (a.empty()) throw InputError(what + ": the checkpoint entry '" + name + "' is empty");
  return a.front();
}

std::size_t write_checkpoint_file(const std::string& path, const CheckpointData& data) {
  std::string out(kMagic);
  put(out, static_cast<std::uint64_t>(data.arrays.size() + data.texts.size()));
  for (const auto& [name, values] : data.arrays) {
    put_name(out, kDoubles, name, values.size());
    out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(double));
  }
  for (const auto& [name, text] : data.texts) {
    put_name(out, kText, name, text.size());
    out += text;
  }
  out.append(kEnd, 8);
  put(out, fnv1a64(out));
  write_file_atomic(path, out);
  return out.size();
}

std::string read_regular_file(const std::string& path, const std::string& what) {
  // O_NONBLOCK: opening a FIFO does not wait for a writer (it is refused below).
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) throw InputError(fmt::format("{}: cannot open the {} file: {}", path, what, std::strerror(errno)));
  struct FdCloser {
    int fd;
    ~FdCloser() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0)
    throw InputError(fmt::format("{}: cannot read the {} file: {}", path, what, std::strerror(errno)));
  if (!S_ISREG(st.st_mode))
    throw InputError(fmt::format("{}: the {} file is not a regular file (a device, FIFO, socket or directory)",
                                 path, what));
  std::string bytes;
  try {
    bytes.resize(static_cast<std::size_t>(st.st_size));
  } catch (const std::bad_alloc&) {
    throw InputError(fmt::format("{}: the {} file's {} bytes do not fit in memory", path, what, st.st_size));
  }
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::read(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw InputError(fmt::format("{}: cannot read the {} file: {}", path, what, std::strerror(errno)));
    if (n == 0) break;  // shrank while read: the caller sees the shorter text
    done += static_cast<std::size_t>(n);
  }
  bytes.resize(done);
  return bytes;
}

CheckpointData read_checkpoint_file(const std::string& path) {
  const std::string bytes = read_regular_file(path, "checkpoint");
  check_seal(bytes, path);
  Reader r(bytes, bytes.size() - kTrailerSize, path);
  CheckpointData data;
  const auto entries = r.get<std::uint64_t>("the entry count");
  if (entries > r.remaining() / kSmallestEntry)
    throw InputError(fmt::format("{}: the checkpoint file is damaged: {} entries cannot fit in its {} bytes", path,
                                 entries, bytes.size()));
  for (std::uint64_t k = 0; k < entries; ++k) {
    const auto kind = r.get<std::uint8_t>("an entry's kind");
    const auto name_size = r.get<std::uint32_t>("an entry's name length");
    const std::string name(r.take(name_size, "an entry's name"), name_size);
    const auto count = r.get<std::uint64_t>("an entry's length");
    if (data.arrays.count(name) || data.texts.count(name))
      throw InputError(path + ": the checkpoint file is damaged: entry '" + name + "' appears twice");
    if (kind == kDoubles) {
      if (count > r.remaining() / sizeof(double))
        throw InputError(fmt::format("{}: the checkpoint file is damaged: entry '{}' declares {} numbers, {} bytes are "
                                     "left", path, name, count, r.remaining()));
      std::vector<double> values(static_cast<std::size_t>(count));
      const char* source = r.take(count * sizeof(double), "an entry's numbers");
      if (count > 0) std::memcpy(values.data(), source, count * sizeof(double));  // an empty vector's data() may be null
      data.arrays[name] = std::move(values);
    } else if (kind == kText) {
      data.texts[name] = std::string(r.take(count, "an entry's text"), static_cast<std::size_t>(count));
    } else {
      throw InputError(fmt::format("{}: the checkpoint file is damaged: entry '{}' has the unknown kind {}", path,
                                   name, static_cast<int>(kind)));
    }
  }
  if (r.remaining() != 0)
    throw InputError(fmt::format("{}: the checkpoint file is damaged: {} bytes after its {} entries", path,
                                 r.remaining(), entries));
  return data;
}

}  // namespace fibrane::io
