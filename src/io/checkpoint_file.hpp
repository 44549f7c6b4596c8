#pragma once
// A checkpoint file: named arrays of doubles and named texts in a small binary container, bit-exact
// (doubles are stored as their 8 bytes, little-endian hosts only), written atomically (temporary file +
// rename), so a reader sees the previous checkpoint or the new one, never a torn file, and sealed by a
// checksum over all its bytes, so a damaged or edited file is refused rather than read.
//
// Layout: the magic line "FIBRANE-CHECKPOINT 2\n", a uint64 entry count, then per entry a uint8 kind
// (0: doubles, 1: text), a uint32 name length and the name, a uint64 element count and the elements; then
// the 8 bytes "END-CKPT" and the uint64 FNV-1a 64 (common/hash.hpp) of every byte before it.
#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace fibrane::io {

struct CheckpointData {
  std::map<std::string, std::vector<double>> arrays;
  std::map<std::string, std::string> texts;

  // The array or text of that name; throws InputError naming `what` (the file) if it is absent.
  const std::vector<double>& array(const std::string& name, const std::string& what) const;
  const std::string& text(const std::string& name, const std::string& what) const;
  // The first element of a one-element array (InputError if absent or empty).
  double scalar(const std::string& name, const std::string& what) const;
};

// Writes `data` to `path` atomically and returns the file's size; throws std::runtime_error on I/O failure.
std::size_t write_checkpoint_file(const std::string& path, const CheckpointData& data);

// Reads a file written by write_checkpoint_file; throws InputError naming the file and what is wrong if
// it is missing, not a regular file, not a checkpoint (or of another format version), truncated, fails
// its checksum, or its entries do not fit in it. No length read from the file is trusted beyond the
// file's size.
CheckpointData read_checkpoint_file(const std::string& path);

// The bytes of the regular file `path` (links followed), as many as its size says; InputError naming the
// file for a missing or unreadable file and for anything that is not a regular file (a device, a FIFO,
// a directory). `what` names the file's role in messages ("checkpoint", "history").
std::string read_regular_file(const std::string& path, const std::string& what);

}  // namespace fibrane::io
