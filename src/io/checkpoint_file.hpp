#pragma once
// A checkpoint file: named arrays of doubles and named texts in a small binary container, bit-exact
// (doubles are stored as their 8 bytes, little-endian hosts only), written atomically (temporary file +
// rename), so a reader sees the previous checkpoint or the new one, never a torn file.
//
// Layout: the magic line "FIBRANE-CHECKPOINT 1\n", a uint64 entry count, then per entry a uint8 kind
// (0: doubles, 1: text), a uint32 name length and the name, a uint64 element count and the elements; the
// file ends with the 8 bytes "END-CKPT".
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

// Reads a file written by write_checkpoint_file; throws InputError naming the file if it is missing,
// not a checkpoint, or truncated.
CheckpointData read_checkpoint_file(const std::string& path);

}  // namespace fibrane::io
