#pragma once
// OpenCV's BORDER_REFLECT_101 of an index, for code that must not depend on OpenCV (the kernels'
// files, which tests/kernels builds with a compiler and Highway alone).

namespace mdbrief::detail {

// The index in [0, n) that pixel i reflects to (gfedcb|abcdefgh|gfedcba), n >= 1.
inline int reflect101(int i, int n) {
  if (n == 1) return 0;
  while (i < 0 || i >= n) i = i < 0 ? -i : 2 * n - 2 - i;
  return i;
}

}  // namespace mdbrief::detail
