#pragma once
// Quadtree spreading of one level's corners (in the spirit of ORB-SLAM's distribution), so
// keypoints cover the image instead of clustering on its most textured part.
#include <vector>

#include <opencv2/core.hpp>

#include "detect/candidate.hpp"

namespace mdbrief::detail {

// Returns at most `budget` candidates, sorted by strongerThan. The area (level pixels, the
// candidates' bounding region) starts as round(width / height) side-by-side cells; the cell
// holding the most candidates is split in four until there are at least `budget` non-empty
// cells or none can be split; each cell then keeps its strongest candidate, and if there
// are more cells than `budget`, the strongest of those are kept.
std::vector<Candidate> spreadWithQuadtree(const std::vector<Candidate>& candidates, int budget,
                                          const cv::Rect& area);

}  // namespace mdbrief::detail
