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

// Set bits of a word. Without a target that has the POPCNT instruction (the default
// build targets baseline x86-64), __builtin_popcountll is a call into libgcc
// (__popcountdi2), 3 % of a KITTI run's CPU samples; the SWAR sum below is inlined:
// bits summed in pairs, nibbles, bytes, then the bytes by one multiplication.
inline int PopCount(std::uint64_t word) {
#if defined(__POPCNT__)
  return __builtin_popcountll(word);
#else
  word -= (word >> 1) & 0x5555555555555555ULL;
  word = (word & 0x3333333333333333ULL) + ((word >> 2) & 0x3333333333333333ULL);
  word = (word + (word >> 4)) & 0x0F0F0F0F0F0F0F0FULL;
  return static_cast<int>((word * 0x0101010101010101ULL) >> 56);
#endif
}

inline int HammingDistance(const Descriptor& a, const Descriptor& b) {
  return PopCount(a[0] ^ b[0]) + PopCount(a[1] ^ b[1]) + PopCount(a[2] ^ b[2]) +
         PopCount(a[3] ^ b[3]);
}

Descriptor DescriptorFromBytes(const std::uint8_t* bytes);
void DescriptorToBytes(const Descriptor& descriptor, std::uint8_t* bytes);

// Bit i (0..255) of the descriptor, in the row's byte order (bit i % 8 of byte i / 8).
inline bool DescriptorBit(const Descriptor& d, int bit) { return (d[bit >> 6] >> (bit & 63)) & 1u; }

// Bitwise majority (ties give 0): the centre of a cluster of binary descriptors.
Descriptor MajorityDescriptor(const std::vector<const Descriptor*>& members);

}  // namespace ocg
