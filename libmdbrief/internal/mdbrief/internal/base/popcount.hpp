#pragma once
// Population count for code compiled for the x86-64 baseline (the library outside its kernels,
// and the kernels' scalar target: bit_count-inl.h): there GCC would turn the builtin into a
// libgcc call, which we measured 4-5x slower in the matcher than this bit-parallel count. With
// POPCNT, and on other CPUs, the builtin. Internal linkage, so a copy compiled with POPCNT can
// never stand in for the baseline one at link time.
#include <cstdint>

namespace mdbrief {
namespace {

inline int popcount64(uint64_t v) noexcept {
#if defined(__POPCNT__) || !defined(__x86_64__)
  return __builtin_popcountll(v);
#else
  v = v - ((v >> 1) & 0x5555555555555555ull);
  v = (v & 0x3333333333333333ull) + ((v >> 2) & 0x3333333333333333ull);
  v = (v + (v >> 4)) & 0x0F0F0F0F0F0F0F0Full;
  return static_cast<int>((v * 0x0101010101010101ull) >> 56);
#endif
}

}  // namespace
}  // namespace mdbrief
