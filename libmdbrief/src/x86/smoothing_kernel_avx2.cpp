// The pyramid smoothing's passes (smoothing_kernels.hpp) vectorised for AVX2 (-mavx2).
#include "smoothing_kernels.hpp"

namespace mdbrief::smoothing_kernels {

SmoothingKernels avx2SmoothingKernels() { return {smoothRow, smoothColumns}; }

}  // namespace mdbrief::smoothing_kernels
