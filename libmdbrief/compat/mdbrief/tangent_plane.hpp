#pragma once
// The single-level path of releases before 0.2, kept for one release: the public headers are
// grouped by part now (mdbrief/mdbrief.hpp includes them all).
#pragma message("mdbrief/tangent_plane.hpp is now mdbrief/camera/tangent_plane.hpp; the old path goes in the next release")
#include "mdbrief/camera/tangent_plane.hpp"
