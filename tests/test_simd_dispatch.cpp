// Each kernel set runs the Highway target its level asks for: every level gives the same bits
// (test_simd_levels.cpp), so only the target a kernel reports can show a wrong dispatch. The
// expected targets are written here from simd_level.hpp's definitions, not taken from the
// library.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include <hwy/targets.h>

#include "describe/descriptor_kernels.hpp"
#include "describe/mask_weight_kernels.hpp"
#include "detect/hessian_kernels.hpp"
#include "detect/resize_kernels.hpp"
#include "detect/smoothing_kernels.hpp"
#include "match/matcher_kernels.hpp"
#include "mdbrief/base/simd_level.hpp"
#include "trainer/comparison_response_kernels.hpp"

namespace mdbrief {
namespace {

// The Highway targets that may serve a level: the scalar level is Highway's emulated 128-bit
// or scalar target, AVX-512 its AVX3 or, with the Ice Lake extensions, AVX3_DL.
std::set<std::string> targetsOf(SimdLevel level) {
  switch (level) {
    case SimdLevel::Portable:
      return {"EMU128", "SCALAR"};
    case SimdLevel::Sse4:
      return {"SSE4"};
    case SimdLevel::Neon:
      return {"NEON"};
    case SimdLevel::Avx2:
      return {"AVX2"};
    case SimdLevel::Avx512:
      return {"AVX3", "AVX3_DL"};
  }
  return {};
}

TEST(SimdDispatch, EveryKernelSetRunsTheTargetOfTheLevelAskedFor) {
  const std::vector<SimdLevel> levels = supportedSimdLevels();
  ASSERT_FALSE(levels.empty());
  for (const SimdLevel level : levels) {
    limitSimdLevel(level);
    const std::set<std::string> expected = targetsOf(level);
    const std::pair<const char*, int64_t> kernels[] = {
        {"descriptor", descriptor_kernels::activeSamplingKernels().target},
        {"mask weights", mask_weight_kernels::activeMaskWeights().target},
        {"hessian", hessian_kernels::activeHessianKernels().target},
        {"resize", resize_kernels::activeResizeKernels().target},
        {"smoothing", smoothing_kernels::activeSmoothingKernels().target},
        {"matcher", matcher_kernels::activeMatcherKernels().target},
        {"trainer responses", train::kernels::activeResponseKernels().target},
    };
    for (const auto& [name, target] : kernels)
      EXPECT_EQ(expected.count(hwy::TargetName(target)), 1u)
          << name << " kernels ran " << hwy::TargetName(target) << " at level " << toString(level);
  }
  limitSimdLevel(SimdLevel::Avx512);
}

}  // namespace
}  // namespace mdbrief
