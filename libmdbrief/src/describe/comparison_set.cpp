#include <stdexcept>

#include "mdbrief/describe/comparison_set.hpp"

namespace mdbrief {

ComparisonSet ComparisonSet::first(int n) const {
  const int size = static_cast<int>(tests.size());
  if (n < 32 || n > size || n % 32 != 0)
    throw std::invalid_argument("test set '" + name + "': cannot take the first " +
                                std::to_string(n) + " tests (need a multiple of 32 in 32.." +
                                std::to_string(size) + ")");
  return ComparisonSet{name, std::vector<ComparisonPair>(tests.begin(), tests.begin() + n), trainingImages};
}

}  // namespace mdbrief
