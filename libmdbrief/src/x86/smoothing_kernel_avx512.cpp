// The pyramid smoothing's passes (smoothing_kernels.hpp) vectorised for AVX-512 (-mavx512f -mavx512bw).
#include "smoothing_kernels.hpp"

namespace mdbrief::smoothing_kernels {

SmoothingKernels avx512SmoothingKernels() { return {smoothRow, smoothColumns}; }

}  // namespace mdbrief::smoothing_kernels
