#pragma once
// The single-level path of releases before 0.2, kept for one release: the public headers are
// grouped by part now (mdbrief/mdbrief.hpp includes them all).
#pragma message("mdbrief/camera_io.hpp is now mdbrief/camera/io.hpp; the old path goes in the next release")
#include "mdbrief/camera/io.hpp"
