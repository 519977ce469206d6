// simd_level(), supported_simd_level() and limit_simd_level(): which kernels the library runs
// (mdbrief/simd_level.hpp), by name.
#include <stdexcept>
#include <string>

#include "bindings.hpp"
#include "mdbrief/simd_level.hpp"

namespace mdbrief::python {

namespace {

constexpr SimdLevel kLevels[] = {SimdLevel::Portable, SimdLevel::Avx2, SimdLevel::Avx512};

SimdLevel parseLevel(const std::string& name) {
  for (const SimdLevel level : kLevels)
    if (toString(level) == name) return level;
  throw py::value_error("level: expected 'portable', 'avx2' or 'avx512', got '" + name + "'");
}

}  // namespace

void bindSimdLevel(py::module_& m) {
  m.def("simd_level", [] { return toString(activeSimdLevel()); },
        "The kernel level the library runs now: 'portable', 'avx2' or 'avx512'.");
  m.def("supported_simd_level", [] { return toString(supportedSimdLevel()); },
        "The highest kernel level this CPU and build support.");
  m.def("limit_simd_level", [](const std::string& level) { limitSimdLevel(parseLevel(level)); }, py::arg("level"),
        "Caps the kernel level for the whole process, e.g. to compare kernels. Every level gives\n"
        "the same results; 'avx512' lifts the cap.");
}

}  // namespace mdbrief::python
