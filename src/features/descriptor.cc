#include "ocg/features/descriptor.h"

#include <cstring>

namespace ocg {

Descriptor DescriptorFromBytes(const std::uint8_t* bytes) {
  Descriptor d;
  std::memcpy(d.data(), bytes, kDescriptorBytes);
  return d;
}

void DescriptorToBytes(const Descriptor& descriptor, std::uint8_t* bytes) {
  std::memcpy(bytes, descriptor.data(), kDescriptorBytes);
}

Descriptor MajorityDescriptor(const std::vector<const Descriptor*>& members) {
  std::array<int, kDescriptorBits> ones{};
  for (const Descriptor* member : members) {
    for (int word = 0; word < 4; ++word) {
      std::uint64_t bits = (*member)[word];
      while (bits != 0) {
        ones[static_cast<std::size_t>(word * 64 + __builtin_ctzll(bits))]++;
        bits &= bits - 1;
      }
    }
  }
  Descriptor centre{};
  const int half = static_cast<int>(members.size());
  for (int bit = 0; bit < kDescriptorBits; ++bit) {
    if (2 * ones[static_cast<std::size_t>(bit)] > half) centre[bit >> 6] |= 1ull << (bit & 63);
  }
  return centre;
}

}  // namespace ocg
