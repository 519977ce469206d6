// simd_level(), supported_simd_level(), supported_simd_levels() and limit_simd_level(): which
// kernels the library runs (mdbrief/base/simd_level.hpp), by name.
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "mdbrief/base/simd_level.hpp"

namespace mdbrief::python {

void bindSimdLevel(py::module_& m) {
  m.def("simd_level", [] { return toString(activeSimdLevel()); },
        "The kernel level the library runs now: 'portable', 'sse4', 'neon', 'avx2' or 'avx512'\n"
        "(the environment variable MDBRIEF_SIMD_LEVEL caps it from the first call on).");
  m.def("supported_simd_level", [] { return toString(supportedSimdLevel()); },
        "The highest kernel level this CPU and build support.");
  m.def("supported_simd_levels",
        [] {
          std::vector<std::string> names;
          for (const SimdLevel level : supportedSimdLevels()) names.push_back(toString(level));
          return names;
        },
        "Every kernel level this CPU and build support, lowest ('portable') first.");
  m.def("limit_simd_level", [](const std::string& level) { limitSimdLevel(parseSimdLevel(level)); }, py::arg("level"),
        "Caps the kernel level for the whole process, e.g. to compare kernels or to measure what a\n"
        "smaller CPU runs. Every level gives the same results; 'avx512' lifts the cap.");
}

}  // namespace mdbrief::python
