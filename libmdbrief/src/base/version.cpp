#include "mdbrief/base/version.hpp"

namespace mdbrief {

const char* version() { return MDBRIEF_VERSION_STRING; }

}  // namespace mdbrief
