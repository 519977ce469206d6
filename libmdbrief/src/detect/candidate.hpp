#pragma once
// A corner found on one pyramid level, in that level's integer pixel coordinates.
#include <tuple>

namespace mdbrief::detail {

struct Candidate {
  int x = 0;
  int y = 0;
  float response = 0.f;  // Harris score (modORB) or normalised Hessian determinant
  int id = 0;            // the caller's index of the candidate (ignored by the ordering)
};

// Strict total order used everywhere the detector ranks corners: stronger first, then by
// position, so the output never depends on the order the corner detector emitted them in.
inline bool strongerThan(const Candidate& a, const Candidate& b) {
  if (a.response != b.response) return a.response > b.response;
  return std::tie(a.y, a.x) < std::tie(b.y, b.x);
}

}  // namespace mdbrief::detail
