// The checkpoint container: every double reads back bit for bit, texts byte for byte, and a damaged,
// forged, foreign or non-regular file is a located InputError (every length bounded by the file's size);
// the history CSV continues after a kept number of rows and knows the hash of its bytes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "common/error.hpp"
#include "common/hash.hpp"
#include "io/checkpoint_file.hpp"
#include "io/csv.hpp"
#include "io/scratch_dir.hpp"

namespace fibrane::io {
namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(CheckpointFile, RoundTripIsBitExact) {
  testing::ScratchDir dir;
  CheckpointData d;
  const double tiny = std::numeric_limits<double>::denorm_min();
  d.arrays["values"] = {0.1, -0.0, 1.0 / 3.0, tiny, std::numeric_limits<double>::max(),
                        std::numeric_limits<double>::quiet_NaN(), -std::numeric_limits<double>::infinity()};
  d.arrays["empty"] = {};
  d.arrays["with space and.dots"] = {42};
  d.texts["files"] = std::string("vtk/a_000001.vtu\nvtk/b\0c\n", 24);
  const std::string path = dir.file("checkpoint.bin");
  write_checkpoint_file(path, d);
  const CheckpointData back = read_checkpoint_file(path);
  ASSERT_EQ(back.arrays.size(), d.arrays.size());
  for (const auto& [name, values] : d.arrays) {
    const auto& read = back.array(name, path);
    ASSERT_EQ(read.size(), values.size()) << name;
    for (std::size_t i = 0; i < values.size(); ++i) EXPECT_TRUE(same_bits(read[i], values[i])) << name << " " << i;
  }
  EXPECT_EQ(back.text("files", path), d.texts.at("files"));
  EXPECT_EQ(back.scalar("with space and.dots", path), 42.0);
  EXPECT_EQ(dir.entry_count(), 1u);  // no temporary left behind
}

TEST(CheckpointFile, DamagedOrForeignFilesAreLocatedInputErrors) {
  testing::ScratchDir dir;
  CheckpointData d;
  d.arrays["q"] = std::vector<double>(100, 1.5);
  const std::string path = dir.file("checkpoint.bin");
  write_checkpoint_file(path, d);
  const std::string bytes = testing::read_text(path);
  auto expect_error = [&](const std::string& content, const char* what) {
    const std::string bad = dir.file("bad.bin");
    std::ofstream(bad, std::ios::binary) << content;
    try {
      read_checkpoint_file(bad);
      ADD_FAILURE() << what << ": no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
  };
  expect_error(bytes.substr(0, bytes.size() - 1), "one byte short");
  expect_error(bytes.substr(0, bytes.size() / 2), "half");
  expect_error(bytes + "x", "trailing byte");
  expect_error("history.csv is not a checkpoint\n", "foreign");
  expect_error("", "empty");
  EXPECT_THROW(read_checkpoint_file(dir.file("missing.bin")), InputError);
  EXPECT_THROW(d.array("absent", path), InputError);
}

// The checksum covers every byte: each single flipped bit anywhere in the file is refused.
TEST(CheckpointFile, EveryFlippedBitIsRefused) {
  testing::ScratchDir dir;
  CheckpointData d;
  d.arrays["q"] = {1.0, 2.0, 3.0};
  d.arrays["step"] = {7};
  d.texts["method"] = "arc_length";
  const std::string path = dir.file("checkpoint.bin"), bad = dir.file("bad.bin");
  write_checkpoint_file(path, d);
  const std::string bytes = testing::read_text(path);
  int refused = 0;
  for (std::size_t at = 0; at < bytes.size(); ++at) {
    std::string damaged = bytes;
    damaged[at] = static_cast<char>(damaged[at] ^ (1 << (at % 8)));
    std::ofstream(bad, std::ios::binary | std::ios::trunc) << damaged;
    try {
      read_checkpoint_file(bad);
      ADD_FAILURE() << "byte " << at << ": accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(bad + ":"), std::string::npos) << e.what();
      ++refused;
    }
  }
  EXPECT_EQ(refused, static_cast<int>(bytes.size()));
}

// A forger who recomputes the checksum still cannot make the reader allocate beyond the file's size.
TEST(CheckpointFile, ResealedLengthsAreBoundedByTheFileSize) {
  testing::ScratchDir dir;
  CheckpointData d;
  d.arrays["q"] = {1.0, 2.0};
  d.texts["name"] = "x";
  const std::string path = dir.file("checkpoint.bin");
  write_checkpoint_file(path, d);
  const std::string bytes = testing::read_text(path);
  auto forged = [&](std::size_t at, std::uint64_t value, std::size_t size, const char* what) {
    std::string b = bytes;
    std::memcpy(b.data() + at, &value, size);
    const std::uint64_t sum = fnv1a64(b.data(), b.size() - 8);
    std::memcpy(b.data() + b.size() - 8, &sum, 8);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << b;
    try {
      read_checkpoint_file(path);
      ADD_FAILURE() << what << ": accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  const std::size_t q_count = bytes.find("q") + 1;  // the first entry: kind, name length 1, "q", count
  forged(21, std::uint64_t{1} << 63, 8, "entries cannot fit");
  forged(q_count, std::uint64_t{1} << 61, 8, "entry 'q' declares 2305843009213693952 numbers");
  forged(q_count - 5, 0xFFFFFFFFu, 4, "an entry's name at byte 34 needs 4294967295 bytes");
  forged(q_count, 1, 8, "damaged");
}

TEST(CheckpointFile, NonRegularFilesAreRefused) {
  testing::ScratchDir dir;
  for (const std::string& path : {std::string("/dev/zero"), dir.path().string()}) {
    try {
      read_checkpoint_file(path);
      ADD_FAILURE() << path << ": accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path + ": the checkpoint file is not a regular file"), std::string::npos)
          << e.what();
    }
  }
}

// A restarted run keeps the first rows of history.csv, cuts off what follows (rows written after the
// checkpoint, a torn last row) and appends.
TEST(CsvWriterResume, KeepsRowsCutsTheRestAndAppends) {
  testing::ScratchDir dir;
  const std::string path = dir.file("history.csv");
  {
    CsvWriter w(path, {"step", "t"});
    for (int i = 0; i < 5; ++i) w.row({double(i), 0.1 * i});
  }
  {
    std::ofstream(path, std::ios::app) << "5,0.5";  // a torn row
  }
  {
    CsvWriter w(path, {"step", "t"}, 3);
    EXPECT_EQ(w.rows_written(), 3u);
    w.row({3, 0.25});
  }
  EXPECT_EQ(testing::read_text(path), "step,t\n0,0\n1,0.1\n2,0.2\n3,0.25\n");
  {
    CsvWriter w(path, {"step", "t"}, 2);  // the hash of the bytes kept, then of those appended
    EXPECT_EQ(w.content_hash(), fnv1a64("step,t\n0,0\n1,0.1\n"));
    w.row({2, 0.5});
    EXPECT_EQ(w.content_hash(), fnv1a64(testing::read_text(path)));
  }
  EXPECT_THROW(CsvWriter(path, {"step", "t"}, 5), InputError);    // fewer rows than the checkpoint's
  EXPECT_THROW(CsvWriter(path, {"step", "time"}, 1), InputError);  // another header
}

}  // namespace
}  // namespace fibrane::io
