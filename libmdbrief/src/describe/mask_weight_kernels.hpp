#pragma once
// The mask weights w(o) of a masked vocabulary's nodes, computed on load (vocabulary_file.cpp):
// one bit count per mask word over every node, the largest part of loading a masked vocabulary
// when counted without a bit-count instruction. Written once in mask_weight_kernels.cpp and
// compiled for every SIMD level (simd_level.hpp).
#include <cstddef>
#include <cstdint>

namespace mdbrief::mask_weight_kernels {

// weights[i] = weightOfOnes[set bits of row i] for `count` rows of `nwords` 32-bit words
// (weightOfOnes has nwords * 32 + 1 entries). Returns the first row without a set bit (its
// weight and the following ones unset), or `count`.
using MaskWeights = size_t (*)(const uint32_t* rows, size_t count, int nwords, const uint32_t* weightOfOnes,
                               uint32_t* weights);

struct MaskWeightKernels {
  MaskWeights weights = nullptr;
  int64_t target = 0;  // the Highway target the kernel was compiled for (HWY_AVX2, ...)
};

// The kernel of the active SIMD level.
MaskWeightKernels activeMaskWeights();

}  // namespace mdbrief::mask_weight_kernels
