// The matcher's kernel for any CPU (compiled for the baseline; matcher_kernel_rows.hpp).
#include "matcher_kernel_rows.hpp"

namespace mdbrief::matcher_kernels {

Nearest nearestTwoPortable(const QueryRow& q, const TrainView& t) { return nearestTwoRows(q, t); }

}  // namespace mdbrief::matcher_kernels
