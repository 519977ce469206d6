#pragma once
// The single-level path of releases before 0.2, kept for one release: the public headers are
// grouped by part now (mdbrief/mdbrief.hpp includes them all).
#pragma message("mdbrief/descriptor.hpp is now mdbrief/describe/descriptor.hpp; the old path goes in the next release")
#include "mdbrief/describe/descriptor.hpp"
