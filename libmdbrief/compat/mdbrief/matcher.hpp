#pragma once
// The single-level path of releases before 0.2, kept for one release: the public headers are
// grouped by part now (mdbrief/mdbrief.hpp includes them all).
#pragma message("mdbrief/matcher.hpp is now mdbrief/match/matcher.hpp; the old path goes in the next release")
#include "mdbrief/match/matcher.hpp"
