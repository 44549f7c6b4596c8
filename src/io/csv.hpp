#pragma once
// History CSV that grows by one row per step and is valid on disk after every row: each row is
// formatted in memory and handed to the OS with a single append write, so a killed run leaves at worst
// a file that ends after the last complete row. Numbers use the shortest text that reads back to the
// identical double (std::to_chars), i.e. full precision without noise digits.
#include <cstdint>
#include <string>
#include <vector>

namespace fibrane::io {

// Shortest decimal text that parses back to exactly `value` ("nan", "inf", "-inf" for non-finite).
std::string format_double(double value);

// Quotes a CSV field if it contains a comma, quote or line break (RFC 4180).
std::string csv_field(const std::string& text);

class CsvWriter {
 public:
  // Creates `path` as a new file holding the header line (replacing whatever had the name, never writing
  // through it: io/atomic_file.hpp).
  CsvWriter(std::string path, std::vector<std::string> columns);
  // Continues an existing file (a restarted run): its header must name `columns`; its first `keep_rows`
  // rows are kept (in a new file renamed onto the name), anything after them is cut off, and rows()
  // appends. Throws InputError naming the file if it is not a regular file (a symbolic link), the header
  // differs or it has fewer complete rows.
  CsvWriter(std::string path, std::vector<std::string> columns, std::size_t keep_rows);
  ~CsvWriter();
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;

  // Appends one row; values.size() must equal the number of columns (std::invalid_argument otherwise).
  void row(const std::vector<double>& values);

  const std::vector<std::string>& columns() const { return columns_; }
  const std::string& path() const { return path_; }
  std::size_t rows_written() const { return rows_; }
  // FNV-1a 64 (common/hash.hpp) of the file's bytes so far: the header and the rows, kept or appended.
  std::uint64_t content_hash() const { return hash_; }

 private:
  void start(const std::string& content);  // the file with `content`, opened for appending
  void write_line(const std::string& line);

  std::string path_;
  std::vector<std::string> columns_;
  int fd_ = -1;
  std::size_t rows_ = 0;
  std::uint64_t hash_ = 0;
};

}  // namespace fibrane::io
