# mdbrief_use_highway(<target>): the target's kernel sources are written once with Google
# Highway (hwy/foreach_target.h) and dispatched by the library's SIMD level
# (libmdbrief/internal/mdbrief/internal/base/simd_dispatch.hpp). Every such target gets the same
# definitions, so every kernel source compiles the same set of targets (HWY_TARGETS) and its
# dispatch table has the same layout:
# - the scalar target always (the portable level), AVX-512 with the Ice Lake extensions too;
# - no SSSE3 (SSE4 is the 128-bit x86 level) and no SVE (NEON is the AArch64 level): fewer
#   copies to compile and test;
# - MDBRIEF_PORTABLE_KERNELS: the scalar target alone.
function(mdbrief_use_highway target)
  if(MDBRIEF_PORTABLE_KERNELS)
    target_compile_definitions(${target} PRIVATE HWY_COMPILE_ONLY_SCALAR MDBRIEF_PORTABLE_KERNELS)
  else()
    target_compile_definitions(${target} PRIVATE HWY_COMPILE_ALL_ATTAINABLE HWY_WANT_AVX3_DL
      "HWY_DISABLED_TARGETS=(HWY_SSSE3|HWY_SVE|HWY_SVE2|HWY_SVE_256|HWY_SVE2_128)")
  endif()
  # The library asks libhwy which x86 targets the CPU runs; a cross-build of the kernels alone
  # (tests/kernels) has Highway's headers only, which is all AArch64 needs.
  if(TARGET hwy::hwy)
    target_link_libraries(${target} PRIVATE hwy::hwy)
  endif()
endfunction()
