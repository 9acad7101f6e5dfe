#pragma once
// 256-bit binary descriptors (ORB's steered BRIEF) and their Hamming distance.

#include <array>
#include <cstdint>
#include <vector>

namespace ocg {

// The 32 bytes of an OpenCV ORB descriptor row, packed into four words so that the
// Hamming distance is four popcounts. Byte order is the row's: DescriptorFromBytes and
// DescriptorToBytes are inverse, so vocabularies keep OpenCV's (and ORB-SLAM2's) bytes.
using Descriptor = std::array<std::uint64_t, 4>;

constexpr int kDescriptorBytes = 32;
constexpr int kDescriptorBits = 256;

inline int HammingDistance(const Descriptor& a, const Descriptor& b) {
  return __builtin_popcountll(a[0] ^ b[0]) + __builtin_popcountll(a[1] ^ b[1]) +
         __builtin_popcountll(a[2] ^ b[2]) + __builtin_popcountll(a[3] ^ b[3]);
}

Descriptor DescriptorFromBytes(const std::uint8_t* bytes);
void DescriptorToBytes(const Descriptor& descriptor, std::uint8_t* bytes);

// Bit i (0..255) of the descriptor, in the row's byte order (bit i % 8 of byte i / 8).
inline bool DescriptorBit(const Descriptor& d, int bit) { return (d[bit >> 6] >> (bit & 63)) & 1u; }

// Bitwise majority (ties give 0): the centre of a cluster of binary descriptors.
Descriptor MajorityDescriptor(const std::vector<const Descriptor*>& members);

}  // namespace ocg
