#include "mdbrief/recognition/bow_vector.hpp"

#include <algorithm>

namespace mdbrief {

float l1Score(const BowVector& a, const BowVector& b) noexcept {
  // Summed in double, in word order, so the score is the same wherever it is computed.
  double sum = 0;
  auto i = a.begin(), j = b.begin();
  while (i != a.end() && j != b.end()) {
    if (i->word < j->word) {
      ++i;
    } else if (j->word < i->word) {
      ++j;
    } else {
      sum += std::min(i->value, j->value);
      ++i;
      ++j;
    }
  }
  return static_cast<float>(sum);
}

}  // namespace mdbrief
