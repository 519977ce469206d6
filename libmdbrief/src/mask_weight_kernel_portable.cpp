// The mask weight kernel for any CPU (compiled for the baseline; mask_weight_rows.hpp).
#include "mask_weight_rows.hpp"

namespace mdbrief::mask_weight_kernels {

size_t maskWeightsPortable(const uint32_t* rows, size_t count, int nwords, const uint32_t* weightOfOnes,
                           uint32_t* weights) {
  return maskWeightRows(rows, count, nwords, weightOfOnes, weights);
}

}  // namespace mdbrief::mask_weight_kernels
