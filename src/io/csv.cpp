#include "io/csv.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "common/error.hpp"
#include "common/hash.hpp"
#include "io/atomic_file.hpp"

namespace fibrane::io {

std::string format_double(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

namespace {

std::string header_line(const std::vector<std::string>& columns) {
  std::string header;
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (i > 0) header += ',';
    header += csv_field(columns[i]);
  }
  return header;
}

}  // namespace

CsvWriter::CsvWriter(std::string path, std::vector<std::string> columns)
    : path_(std::move(path)), columns_(std::move(columns)), hash_(kFnv1aOffset) {
  if (columns_.empty()) throw std::invalid_argument(path_ + ": a CSV file needs at least one column");
  start(header_line(columns_) + "\n");
}

CsvWriter::CsvWriter(std::string path, std::vector<std::string> columns, std::size_t keep_rows)
    : path_(std::move(path)), columns_(std::move(columns)) {
  const std::string header = header_line(columns_);
  struct stat st {};
  if (::lstat(path_.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    throw InputError(path_ + ": cannot continue it: it is not a regular file (a symbolic link or another kind)");
  std::ifstream in(path_, std::ios::binary);
  if (!in) throw InputError(path_ + ": cannot continue it: the file cannot be read");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (text.compare(0, header.size() + 1, header + "\n") != 0)
    throw InputError(path_ + ": cannot continue it: its header is not this case's history columns");
  std::size_t end = header.size() + 1;
  for (std::size_t k = 0; k < keep_rows; ++k) {
    const std::size_t newline = text.find('\n', end);
    if (newline == std::string::npos)
      throw InputError(fmt::format("{}: cannot continue it: it has {} complete rows, the checkpoint needs {}", path_,
                                   k, keep_rows));
    end = newline + 1;
  }
  start(text.substr(0, end));
  rows_ = keep_rows;
}

void CsvWriter::start(const std::string& content) {
  // A new file with the content, renamed onto the name: whatever was there (a symbolic link, another name of
  // a hard-linked file) is replaced, not written to.
  write_file_atomic(path_, content);
  fd_ = ::open(path_.c_str(), O_WRONLY | O_APPEND | O_NOFOLLOW | O_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error(fmt::format("{}: cannot open: {}", path_, std::strerror(errno)));
  hash_ = fnv1a64(content);
}

CsvWriter::~CsvWriter() {
  if (fd_ >= 0) ::close(fd_);
}

void CsvWriter::row(const std::vector<double>& values) {
  if (values.size() != columns_.size()) {
    throw std::invalid_argument(
        fmt::format("{}: row has {} values for {} columns", path_, values.size(), columns_.size()));
  }
  std::string line;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i > 0) line += ',';
    line += format_double(values[i]);
  }
  write_line(line);
  ++rows_;
}

void CsvWriter::write_line(const std::string& line) {
  const std::string text = line + "\n";
  // One write(2) per line; loop only for the (regular-file-unlikely) partial write or EINTR.
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd_, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw std::runtime_error(fmt::format("{}: write failed: {}", path_, std::strerror(errno)));
    done += static_cast<std::size_t>(n);
  }
  hash_ = fnv1a64(text, hash_);
}

}  // namespace fibrane::io
