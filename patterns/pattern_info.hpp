#pragma once
// What every generated pattern header in this folder defines (written by
// trainer/pattern_writer.hpp): its tests and one PatternInfo. Self-contained, so the patterns
// depend on nothing; the runtime library reads them into mdbrief::ComparisonSet (mdbrief/describe/comparison_set.hpp,
// libmdbrief/src/describe/patterns.cpp).
#include <cstdint>

namespace mdbrief::patterns {

// One test: offsets {x1, y1, x2, y2} of mdbrief::ComparisonPair.
using TestRow = int8_t[4];

struct PatternInfo {
  const char* name;       // registry name, e.g. "brief_random_512"
  const TestRow* tests;   // sorted as emitted: the first N tests form the N-bit descriptor
  int count;
  const char* description;  // one line: how it was made
  // Digests (16 hex digits, space-separated) of the decoded grey pixels of the images the set
  // was learned from, so an evaluation can prove it never saw them; "" for a random set.
  const char* trainingImages;
};

}  // namespace mdbrief::patterns
