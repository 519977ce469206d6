// simd_level(), supported_simd_level() and limit_simd_level(): which kernels the library runs
// (mdbrief/simd_level.hpp), by name.
#include <string>

#include "bindings.hpp"
#include "mdbrief/simd_level.hpp"

namespace mdbrief::python {

void bindSimdLevel(py::module_& m) {
  m.def("simd_level", [] { return toString(activeSimdLevel()); },
        "The kernel level the library runs now: 'portable', 'avx2' or 'avx512'.");
  m.def("supported_simd_level", [] { return toString(supportedSimdLevel()); },
        "The highest kernel level this CPU and build support.");
  m.def("limit_simd_level", [](const std::string& level) { limitSimdLevel(parseSimdLevel(level)); }, py::arg("level"),
        "Caps the kernel level for the whole process, e.g. to compare kernels. Every level gives\n"
        "the same results; 'avx512' lifts the cap.");
}

}  // namespace mdbrief::python
