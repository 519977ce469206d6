#pragma once
// The single-level path of releases before 0.2, kept for one release: the public headers are
// grouped by part now (mdbrief/mdbrief.hpp includes them all).
#pragma message("mdbrief/camera_ocam.hpp is now mdbrief/camera/ocam.hpp; the old path goes in the next release")
#include "mdbrief/camera/ocam.hpp"
