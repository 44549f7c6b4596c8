#include "io/yaml_guard.hpp"

#include <fmt/format.h>
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/exceptions.h>
#include <yaml-cpp/parser.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <sstream>

#include "common/error.hpp"
#include "io/utf8.hpp"

namespace fibrane::io {
namespace {

int line_at(const std::string& text, std::size_t offset) {
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(offset), '\n'));
}

// Walks the parser's events: refuses anchors, aliases, explicit tags, too many or too deeply nested nodes.
class GuardHandler final : public YAML::EventHandler {
 public:
  explicit GuardHandler(const std::string& source) : source_(source) {}
  void OnDocumentStart(const YAML::Mark& mark) override {
    if (++documents_ > 1) fail(mark, "a second YAML document ('---'): a case file holds exactly one");
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override { node(mark, "", anchor); }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override {
    fail(mark, "YAML aliases (*name) are not allowed in a case file: write the value out");
  }
  void OnScalar(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor, const std::string&) override {
    node(mark, tag, anchor);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value) override {
    open(mark, tag, anchor);
  }
  void OnSequenceEnd() override { --depth_; }
  void OnMapStart(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value) override {
    open(mark, tag, anchor);
  }
  void OnMapEnd() override { --depth_; }
  void OnAnchor(const YAML::Mark& mark, const std::string&) override {
    fail(mark, "YAML anchors (&name) are not allowed in a case file: write the value out");
  }

 private:
  [[noreturn]] void fail(const YAML::Mark& mark, const std::string& what) const {
    throw InputError(fmt::format("{}:{}: {}", source_, mark.line + 1, what));
  }
  void node(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor) {
    if (anchor != YAML::NullAnchor) fail(mark, "YAML anchors (&name) are not allowed in a case file");
    // Plain nodes carry the tag "?", quoted scalars "!"; anything else was written explicitly.
    if (!tag.empty() && tag != "?" && tag != "!")
      fail(mark, fmt::format("explicit YAML tags ('{}') are not allowed in a case file: write plain values", tag));
    if (++nodes_ > kMaxYamlNodes)
      fail(mark, fmt::format("more than {} YAML nodes: a case file this large is not supported", kMaxYamlNodes));
  }
  void open(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor) {
    node(mark, tag, anchor);
    if (++depth_ > kMaxYamlDepth) fail(mark, fmt::format("lists and maps nested more than {} deep", kMaxYamlDepth));
  }
  const std::string& source_;
  std::size_t nodes_ = 0;
  int depth_ = 0, documents_ = 0;
};

}  // namespace

namespace {

// What a non-regular file is, for the message.
const char* file_kind(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  return "not a regular file";
}

[[noreturn]] void refuse_kind(const std::string& path, mode_t mode) {
  throw InputError(
      fmt::format("{}: is {}, not a case file (a case file must be a regular file)", path, file_kind(mode)));
}

}  // namespace

// A FIFO or a device would block open() or read() (or never end): the file's type is checked before it is
// opened, and again on the open descriptor (opened non-blocking, so that a FIFO put there in between does
// not block either).
std::string read_text_limited(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) == 0 && !S_ISREG(info.st_mode)) refuse_kind(path, info.st_mode);
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw InputError(fmt::format("{}: cannot open the file for reading", path));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  if (::fstat(fd, &info) != 0) throw InputError(fmt::format("{}: cannot read the file", path));
  if (!S_ISREG(info.st_mode)) refuse_kind(path, info.st_mode);
  std::string text(kMaxYamlBytes + 1, '\0');
  std::size_t size = 0;
  while (size < text.size()) {
    const ssize_t got = ::read(fd, text.data() + size, text.size() - size);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) throw InputError(fmt::format("{}: cannot read the file: {}", path, std::strerror(errno)));
    if (got == 0) break;
    size += static_cast<std::size_t>(got);
  }
  text.resize(size);
  if (text.size() > kMaxYamlBytes)
    throw InputError(fmt::format("{}: the file is larger than {} MiB: a case file this large is not supported",
                                 path, kMaxYamlBytes >> 20));
  return text;
}

void check_yaml_text(const std::string& text, const std::string& source_name) {
  if (text.size() > kMaxYamlBytes)
    throw InputError(fmt::format("{}: more than {} MiB of YAML", source_name, kMaxYamlBytes >> 20));
  if (const std::size_t bad = find_invalid_utf8(text, false); bad != std::string::npos) {
    const unsigned char c = static_cast<unsigned char>(text[bad]);
    throw InputError(fmt::format("{}:{}: {} (byte 0x{:02X} at offset {}): a case file must be UTF-8 text",
                                 source_name, line_at(text, bad),
                                 c < 0x80 ? "a control character" : "invalid UTF-8", c, bad));
  }
  std::istringstream in(text);
  GuardHandler handler(source_name);
  try {
    YAML::Parser parser(in);
    while (parser.HandleNextDocument(handler)) {
    }
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}:{}: YAML syntax error: {}", source_name, e.mark.line + 1, e.msg));
  }
}

}  // namespace fibrane::io
