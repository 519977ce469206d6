// The matcher's kernel for AVX2 CPUs, compiled with -mavx2 -mpopcnt: the row kernel with the
// POPCNT instruction.
#include "matcher_kernel_rows.hpp"

namespace mdbrief::matcher_kernels {

Nearest nearestTwoAvx2(const QueryRow& q, const TrainView& t) { return nearestTwoRows(q, t); }

}  // namespace mdbrief::matcher_kernels
