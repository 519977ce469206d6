// mdbrief.presets(): the named settings of mdbrief/api/presets.hpp, which MdBrief(preset=...) and
// match(preset=...) start from.
#include "bindings.hpp"
#include "mdbrief/api/presets.hpp"
#include "presets.hpp"

namespace mdbrief::python {

Preset presetFrom(const std::string& name) {
  try {
    return parsePreset(name);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
}

void bindPresets(py::module_& m) {
  m.def("presets", [] { return namesOf(kPresetNames); }, R"doc(
The names of the presets, MdBrief(camera, preset=...) and match(..., preset=...) start from:
'tracking' (the library's defaults), 'matching' (512 bits and a stricter ratio, for wide
baselines) and 'paper' (the paper's modORB pipeline). docs/RESULTS.md "Real images: what a
tracker keeps" has their measurements.)doc");
}

}  // namespace mdbrief::python
