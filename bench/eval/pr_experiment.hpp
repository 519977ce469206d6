#pragma once
// The precision-recall comparison of the paper's "Results on Real Data": every method on the
// same detected keypoints (the project's Detector, `keypoints` strongest; AKAZE on its own),
// mean PR curve per sequence group, summary numbers. Writes eval_<group>_curves.csv and
// eval_summary.csv.
#include <string>
#include <vector>

#include "descriptor_method.hpp"
#include "eval_datasets.hpp"

namespace mdbrief::eval {

struct EvalGroup {
  std::string name;  // "perspective", "fisheye", "user"
  std::vector<EvalSequence> sequences;
};

struct PrOptions {
  std::string outDir;
  int keypoints = 300;
  double radiusPx = 3.0;
  int curveSteps = 100;
};

// The paper's comparison set; with studies also the length study (32, 64 bits) and the
// test-set study (every name of builtinTestSetNames() at run time).
std::vector<MethodSpec> standardPrMethods(bool withStudies = true);

void runPrecisionRecall(const std::vector<EvalGroup>& groups, const std::vector<MethodSpec>& methods,
                        const PrOptions& options);

}  // namespace mdbrief::eval
