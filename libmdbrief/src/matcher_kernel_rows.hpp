#pragma once
// The row-major matcher kernel, shared by the portable and the AVX2 translation units: each
// includes it once and compiles it with its own flags, so popcount64 (popcount.hpp) is the
// bit-parallel count in one and the POPCNT instruction in the other. Internal linkage keeps the
// two copies apart.
#include <cstring>

#include "matcher_kernels.hpp"
#include "popcount.hpp"

namespace mdbrief::matcher_kernels {
namespace {

inline uint64_t longWord(const uint32_t* p, int k) {
  uint64_t v;
  std::memcpy(&v, p + 2 * k, 8);
  return v;
}

// One train row at a time in index order, 64-bit popcounts plus a 32-bit tail word for odd
// word counts.
template <bool Masked>
Nearest nearestTwoRows(const QueryRow& q, const TrainView& t) {
  const int nwords = t.nwords;
  const int nlong = nwords / 2;
  uint64_t qd[kMaxWords / 2], ql[kMaxWords / 2];
  std::memcpy(qd, q.d, sizeof(uint64_t) * nlong);
  if constexpr (Masked) std::memcpy(ql, q.l, sizeof(uint64_t) * nlong);
  Nearest n;
  for (int j = 0; j < t.count; ++j) {
    const uint32_t* row = t.desc + static_cast<size_t>(j) * nwords;
    uint32_t d;
    if constexpr (!Masked) {
      d = 0;
      for (int k = 0; k < nlong; ++k) d += popcount64(longWord(row, k) ^ qd[k]);
      if (nwords & 1) d += popcount64(row[nwords - 1] ^ q.d[nwords - 1]);
    } else {
      const uint32_t* mask = t.mask + static_cast<size_t>(j) * nwords;
      uint32_t a = 0, c = 0;
      for (int k = 0; k < nlong; ++k) {
        const uint64_t x = longWord(row, k) ^ qd[k];
        a += popcount64(x & ql[k]);
        c += popcount64(x & longWord(mask, k));
      }
      if (nwords & 1) {
        const uint32_t x = row[nwords - 1] ^ q.d[nwords - 1];
        a += popcount64(x & q.l[nwords - 1]);
        c += popcount64(x & mask[nwords - 1]);
      }
      d = a * q.w + c * t.weight[j];
    }
    if (d < n.best) {  // strict: ties keep the lowest index
      n.second = n.best;
      n.best = d;
      n.index = j;
    } else {
      n.second = d < n.second ? d : n.second;  // no std::min: no template instantiated here
    }
  }
  return n;
}

inline Nearest nearestTwoRows(const QueryRow& q, const TrainView& t) {
  return t.mask ? nearestTwoRows<true>(q, t) : nearestTwoRows<false>(q, t);
}

}  // namespace
}  // namespace mdbrief::matcher_kernels
