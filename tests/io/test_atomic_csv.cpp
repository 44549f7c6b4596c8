// Atomic replacement and the history CSV: nothing half-written is ever visible, and every number read
// back from the CSV is bitwise the double that was written.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>

#include "common/error.hpp"
#include "io/atomic_file.hpp"
#include "io/csv.hpp"
#include "io/scratch_dir.hpp"

namespace fibrane::io {
namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  for (std::size_t end; (end = text.find('\n', start)) != std::string::npos; start = end + 1) {
    lines.push_back(text.substr(start, end - start));
  }
  EXPECT_EQ(start, text.size()) << "file does not end with a complete line";
  return lines;
}

std::vector<double> parse_row(const std::string& line) {
  std::vector<double> values;
  const char* p = line.c_str();
  while (true) {
    char* end = nullptr;
    values.push_back(std::strtod(p, &end));
    EXPECT_NE(end, p) << line;
    if (*end != ',') {
      EXPECT_EQ(*end, '\0') << line;
      return values;
    }
    p = end + 1;
  }
}

TEST(AtomicFile, CommitReplacesAndLeavesNoTemporary) {
  testing::ScratchDir dir;
  const std::string path = dir.file("summary.json");
  write_file_atomic(path, "old");
  {
    AtomicFileWriter out(path);
    out << "new " << 42;
    EXPECT_TRUE(std::filesystem::exists(out.temporary_path()));
    EXPECT_EQ(testing::read_text(path), "old");  // target untouched until commit
    out.commit();
    EXPECT_FALSE(std::filesystem::exists(out.temporary_path()));
  }
  EXPECT_EQ(testing::read_text(path), "new 42");
  EXPECT_EQ(dir.entry_count(), 1u);
}

TEST(AtomicFile, UncommittedWriterLeavesOldFile) {
  testing::ScratchDir dir;
  const std::string path = dir.file("state.vtu");
  write_file_atomic(path, "complete old content");
  std::string temporary;
  {
    AtomicFileWriter out(path);
    temporary = out.temporary_path();
    out << "partial new content";
    out.stream().flush();
  }  // e.g. an exception while assembling the output
  EXPECT_EQ(testing::read_text(path), "complete old content");
  EXPECT_FALSE(std::filesystem::exists(temporary));
  EXPECT_EQ(dir.entry_count(), 1u);
}

TEST(AtomicFile, UnwritableDirectoryThrows) {
  testing::ScratchDir dir;
  EXPECT_THROW(write_file_atomic(dir.file("no/such/dir/file.txt"), "x"), std::runtime_error);
}

// A symbolic link or a second hard link at the target's name is replaced by a new file: the link's target
// and the other name keep their content.
TEST(AtomicFile, ReplacesLinksWithoutWritingThroughThem) {
  testing::ScratchDir dir;
  testing::write_text(dir.file("target"), "precious");
  std::filesystem::create_symlink(dir.file("target"), dir.file("linked.json"));
  write_file_atomic(dir.file("linked.json"), "new");
  EXPECT_EQ(testing::read_text(dir.file("target")), "precious");
  EXPECT_TRUE(std::filesystem::is_regular_file(std::filesystem::symlink_status(dir.file("linked.json"))));
  EXPECT_EQ(testing::read_text(dir.file("linked.json")), "new");
  std::filesystem::create_hard_link(dir.file("target"), dir.file("hard.vtu"));
  write_file_atomic(dir.file("hard.vtu"), "replaced");
  EXPECT_EQ(testing::read_text(dir.file("target")), "precious");
  EXPECT_EQ(testing::read_text(dir.file("hard.vtu")), "replaced");
}

// A new history file replaces a link at its name, and a continued one too; a continued history that is a
// symbolic link is refused.
TEST(Csv, NeverWritesThroughALink) {
  testing::ScratchDir dir;
  testing::write_text(dir.file("target"), "precious");
  std::filesystem::create_symlink(dir.file("target"), dir.file("history.csv"));
  EXPECT_THROW(CsvWriter(dir.file("history.csv"), {"step"}, 0), InputError);
  {
    CsvWriter csv(dir.file("history.csv"), {"step"});
    csv.row({0.0});
  }
  EXPECT_EQ(testing::read_text(dir.file("target")), "precious");
  EXPECT_EQ(testing::read_text(dir.file("history.csv")), "step\n0\n");
  std::filesystem::create_hard_link(dir.file("history.csv"), dir.file("copy.csv"));
  {
    CsvWriter csv(dir.file("history.csv"), {"step"}, 1);
    csv.row({1.0});
  }
  EXPECT_EQ(testing::read_text(dir.file("copy.csv")), "step\n0\n");
  EXPECT_EQ(testing::read_text(dir.file("history.csv")), "step\n0\n1\n");
}

TEST(Csv, HeaderAndRowsRoundTripBitwise) {
  testing::ScratchDir dir;
  const std::string path = dir.file("history.csv");
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-300, 300);
  std::vector<std::vector<double>> rows = {
      {0.1, 1.0 / 3.0, -0.0},
      {std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::max(), -1e-300},
      {std::nextafter(1.0, 2.0), 123456789012345678.0, 5e-324},
  };
  for (int i = 0; i < 50; ++i) {
    rows.push_back({std::ldexp(mantissa(random), exponent(random)), mantissa(random), double(i)});
  }
  {
    CsvWriter csv(path, {"t", "energy", "gap, min"});
    for (std::size_t r = 0; r < rows.size(); ++r) {
      csv.row(rows[r]);
      // Valid on disk after every row: header plus r+1 complete lines, nothing buffered.
      EXPECT_EQ(split_lines(testing::read_text(path)).size(), r + 2);
    }
    EXPECT_THROW(csv.row({1.0}), std::invalid_argument);
    EXPECT_EQ(csv.rows_written(), rows.size());
  }
  const std::vector<std::string> lines = split_lines(testing::read_text(path));
  ASSERT_EQ(lines.size(), rows.size() + 1);
  EXPECT_EQ(lines[0], "t,energy,\"gap, min\"");
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const std::vector<double> back = parse_row(lines[r + 1]);
    ASSERT_EQ(back.size(), rows[r].size());
    for (std::size_t c = 0; c < back.size(); ++c) {
      EXPECT_TRUE(same_bits(back[c], rows[r][c])) << lines[r + 1] << " column " << c;
    }
  }
  EXPECT_EQ(lines[1], "0.1,0.3333333333333333,-0");  // shortest round-trip text, not %.17g noise
}

TEST(Csv, NonFiniteValuesAreWrittenReadably) {
  EXPECT_EQ(format_double(std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(format_double(-std::numeric_limits<double>::infinity()), "-inf");
  EXPECT_EQ(format_double(2.5e-7), "2.5e-07");
  EXPECT_EQ(csv_field("a\"b"), "\"a\"\"b\"");
}

}  // namespace
}  // namespace fibrane::io
