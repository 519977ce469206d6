#pragma once
// The random BRIEF test set (Calonder et al., sampling strategy G II): both points of a test
// drawn independently from an isotropic Gaussian around the keypoint, sigma = S/5 for the patch
// size S = 32 (sigma^2 = S^2/25), rounded to integer offsets and clipped to [-15, 14], the
// range of the trainer's candidate tests (the patch's 1-pixel border excluded).
#include <cstdint>
#include <string>
#include <vector>

#include "trainer/pattern_writer.hpp"
#include "mdbrief/describe/comparison_set.hpp"

namespace mdbrief::train {

struct RandomPatternOptions {
  int tests = 512;          // number of tests (multiple of 32)
  uint32_t seed = 20170529; // std::mt19937 seed; the shipped brief_random_512 uses the default
  std::string name;         // registry name; empty = "brief_random_<tests>"
};

// count distinct tests: no test compares a pixel with itself, no test repeats another (in
// either point order). Portable: std::mt19937 plus an own Box-Muller transform, so every
// standard library gives the same set. Throws std::invalid_argument if count < 1.
std::vector<ComparisonPair> gaussianRandomComparisons(int count, uint32_t seed);

// The set with the header comment and per-test comments (test length in pixels).
PatternDocument randomPatternDocument(const RandomPatternOptions& options);

}  // namespace mdbrief::train
