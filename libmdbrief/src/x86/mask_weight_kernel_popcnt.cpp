// The mask weight kernel for CPUs with POPCNT (every one of the AVX2 level), compiled with
// -mpopcnt (mask_weight_rows.hpp).
#include "mask_weight_rows.hpp"

namespace mdbrief::mask_weight_kernels {

size_t maskWeightsPopcnt(const uint32_t* rows, size_t count, int nwords, const uint32_t* weightOfOnes,
                         uint32_t* weights) {
  return maskWeightRows(rows, count, nwords, weightOfOnes, weights);
}

}  // namespace mdbrief::mask_weight_kernels
