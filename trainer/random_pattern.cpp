#include "trainer/random_pattern.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>
#include <stdexcept>
#include <tuple>

namespace mdbrief::train {

namespace {

constexpr int kMinOffset = -kPatchHalf + 1;  // -15: the border column/row 0 is excluded
constexpr int kMaxOffset = kPatchHalf - 2;   // 14: the border column/row 31 is excluded
constexpr double kSigma = kPatchSize / 5.0;  // BRIEF G II: sigma^2 = S^2 / 25

// Standard normal deviates from std::mt19937 (whose output sequence the standard fixes) with
// the Box-Muller transform; std::normal_distribution's algorithm is implementation-defined.
class PortableGaussian {
 public:
  explicit PortableGaussian(uint32_t seed) : engine_(seed) {}
  double next() {
    if (hasSpare_) {
      hasSpare_ = false;
      return spare_;
    }
    const double u1 = uniform(), u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double phi = 2.0 * M_PI * u2;
    spare_ = r * std::sin(phi);
    hasSpare_ = true;
    return r * std::cos(phi);
  }

 private:
  // In (0, 1): never 0, so the logarithm is finite.
  double uniform() { return (static_cast<double>(engine_()) + 0.5) / 4294967296.0; }

  std::mt19937 engine_;
  double spare_ = 0.0;
  bool hasSpare_ = false;
};

int8_t sampleOffset(PortableGaussian& g) {
  const long v = std::lround(g.next() * kSigma);
  return static_cast<int8_t>(std::clamp<long>(v, kMinOffset, kMaxOffset));
}

}  // namespace

std::vector<ComparisonPair> gaussianRandomComparisons(int count, uint32_t seed) {
  if (count < 1) throw std::invalid_argument("random test set: count must be positive");
  PortableGaussian gauss(seed);
  std::set<std::tuple<int, int, int, int>> seen;
  std::vector<ComparisonPair> tests;
  tests.reserve(count);
  while (static_cast<int>(tests.size()) < count) {
    ComparisonPair t;
    t.x1 = sampleOffset(gauss);
    t.y1 = sampleOffset(gauss);
    t.x2 = sampleOffset(gauss);
    t.y2 = sampleOffset(gauss);
    if (t.x1 == t.x2 && t.y1 == t.y2) continue;  // compares a pixel with itself
    // A swapped test is the same test negated: as redundant as an exact repeat.
    if (!seen.insert({t.x1, t.y1, t.x2, t.y2}).second) continue;
    if (seen.count({t.x2, t.y2, t.x1, t.y1})) continue;
    tests.push_back(t);
  }
  return tests;
}

PatternDocument randomPatternDocument(const RandomPatternOptions& options) {
  PatternDocument doc;
  doc.name = options.name.empty() ? "brief_random_" + std::to_string(options.tests) : options.name;
  doc.tests = gaussianRandomComparisons(options.tests, options.seed);
  doc.generator = "mdbrief-pattern-random --tests " + std::to_string(options.tests) +
                  " --seed " + std::to_string(options.seed) +
                  (options.name.empty() ? "" : " --name " + options.name);
  doc.description = "BRIEF G II random tests: isotropic Gaussian, sigma = S/5 = 6.4 px, "
                    "clipped to [-15, 14], seed " + std::to_string(options.seed);
  doc.provenance = {
      "Points drawn from std::mt19937 + Box-Muller (portable), rounded to integer offsets,",
      "clipped to [-15, 14]; self-comparisons and repeated tests are rejected.",
      "Per test: the Euclidean length of the test in pixels."};
  for (const ComparisonPair& t : doc.tests) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "length %.1f", std::hypot(t.x2 - t.x1, t.y2 - t.y1));
    doc.testComments.emplace_back(buf);
  }
  return doc;
}

}  // namespace mdbrief::train
