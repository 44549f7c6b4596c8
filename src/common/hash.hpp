#pragma once
// 64-bit FNV-1a, the checksum of checkpoints and the fingerprint of the texts they vouch for (the case
// text, history.csv's rows). Any change of a single byte changes the hash (each step, xor with the byte
// then multiplication by an odd prime, is a bijection of the 64-bit state); it is not a cryptographic
// hash. A running hash continues from the value returned for the bytes before.
#include <cstddef>
#include <cstdint>
#include <string>

namespace fibrane {

inline constexpr std::uint64_t kFnv1aOffset = 14695981039346656037ULL;

inline std::uint64_t fnv1a64(const char* data, std::size_t size, std::uint64_t hash = kFnv1aOffset) {
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= static_cast<unsigned char>(data[i]);
    hash *= 1099511628211ULL;
  }
  return hash;
}

inline std::uint64_t fnv1a64(const std::string& text, std::uint64_t hash = kFnv1aOffset) {
  return fnv1a64(text.data(), text.size(), hash);
}

}  // namespace fibrane
