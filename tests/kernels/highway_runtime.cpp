// The one function of libhwy that the kernels reference, for a cross-build that has Highway's
// headers but not its library (scripts/test-arm.sh). The library chooses the target itself
// (mdbrief/internal/base/simd_dispatch.hpp) and never calls SupportedTargets() outside x86.
// Should it run, it answers as libhwy does on AArch64, where NEON is part of the base
// instruction set.
#include <hwy/highway.h>

namespace hwy {

int64_t SupportedTargets() { return HWY_TARGETS; }

}  // namespace hwy
