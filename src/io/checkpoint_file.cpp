#include "io/checkpoint_file.hpp"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>

#include "common/error.hpp"
#include "io/atomic_file.hpp"

namespace fibrane::io {
namespace {

constexpr char kMagic[] = "FIBRANE-CHECKPOINT 1\n";
constexpr char kEnd[] = "END-CKPT";
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

// Sequential reader of the file's bytes; every read past the end is a located InputError.
class Reader {
 public:
  Reader(const std::string& bytes, const std::string& path) : bytes_(bytes), path_(path) {}
  template <typename T>
  T get() {
    T value;
    std::memcpy(&value, take(sizeof(T)), sizeof(T));
    return value;
  }
  const char* take(std::size_t n) {
    if (n > bytes_.size() - pos_) throw InputError(path_ + ": the checkpoint file is truncated or damaged");
    const char* p = bytes_.data() + pos_;
    pos_ += n;
    return p;
  }
  std::size_t remaining() const { return bytes_.size() - pos_; }

 private:
  const std::string& bytes_;
  const std::string& path_;
  std::size_t pos_ = 0;
};

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
  write_file_atomic(path, out);
  return out.size();
}

CheckpointData read_checkpoint_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": no checkpoint there (cannot open the file)");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t magic = sizeof(kMagic) - 1;
  if (bytes.compare(0, magic, kMagic) != 0) throw InputError(path + ": not a fibrane checkpoint file");
  Reader r(bytes, path);
  r.take(magic);
  CheckpointData data;
  const auto entries = r.get<std::uint64_t>();
  for (std::uint64_t k = 0; k < entries; ++k) {
    const auto kind = r.get<std::uint8_t>();
    const auto name_size = r.get<std::uint32_t>();
    const std::string name(r.take(name_size), name_size);
    const auto count = r.get<std::uint64_t>();
    if (kind == kDoubles) {
      if (count > r.remaining() / sizeof(double)) throw InputError(path + ": the checkpoint file is truncated or damaged");
      std::vector<double> values(count);
      const char* source = r.take(count * sizeof(double));
      if (count > 0) std::memcpy(values.data(), source, count * sizeof(double));  // an empty vector's data() may be null
      data.arrays[name] = std::move(values);
    } else if (kind == kText) {
      data.texts[name] = std::string(r.take(count), count);
    } else {
      throw InputError(path + ": the checkpoint file is damaged (unknown entry kind)");
    }
  }
  if (r.remaining() != 8 || std::memcmp(r.take(8), kEnd, 8) != 0)
    throw InputError(path + ": the checkpoint file is truncated or damaged");
  return data;
}

}  // namespace fibrane::io
