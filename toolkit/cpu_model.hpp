#pragma once
// The name of the CPU this process runs on, for speed figures that say where they were measured
// (the benchmarks' context, `mdbrief bench`).
#include <string>

namespace mdbrief::toolkit {

// /proc/cpuinfo's "model name" (x86), else its implementer and part numbers (ARM), else the
// machine type from uname(2); never empty.
std::string cpuModel();

}  // namespace mdbrief::toolkit
