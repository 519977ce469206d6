#pragma once
// The preset a keyword names (bind_presets.cpp), for MdBrief and match.
#include <string>

#include "mdbrief/api/presets.hpp"

namespace mdbrief::python {

// ValueError "preset 'x' is not one of: tracking, matching, paper" for an unknown name.
Preset presetFrom(const std::string& name);

}  // namespace mdbrief::python
