// The two functions of libhwy that the kernels reference, for a cross-build that has Highway's
// headers but not its library (scripts/test-arm.sh). HWY_EXPORT's first table slot
// (hwy::FunctionCache::ChooseAndCall) names them; the library never calls that slot, as it
// chooses the target itself (mdbrief/internal/base/simd_dispatch.hpp), and never calls
// SupportedTargets() outside x86. Should either run, it answers as libhwy does on AArch64,
// where NEON is part of the base instruction set.
#include <hwy/highway.h>

namespace hwy {

int64_t SupportedTargets() { return HWY_TARGETS; }

ChosenTarget& GetChosenTarget() {
  static ChosenTarget chosen;
  return chosen;
}

}  // namespace hwy
