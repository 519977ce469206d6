#pragma once
// Deprecated: the header of 0.2, kept so that existing includes compile. TestSet and TestPair
// are now ComparisonSet and ComparisonPair (the deprecated aliases live in comparison_set.hpp).
#include "mdbrief/describe/comparison_set.hpp"
