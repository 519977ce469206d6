// The `mdbrief` Python module (imported through the package python/mdbrief/__init__.py).
#include "bindings.hpp"
#include "mdbrief/base/version.hpp"

PYBIND11_MODULE(_mdbrief, m) {
  mdbrief::python::translateExceptions();
  m.attr("__version__") = mdbrief::version();
  m.doc() = "mdbrief: distorted binary descriptors (BRIEF, dBRIEF, mdBRIEF) for calibrated fisheye cameras.";
  mdbrief::python::bindCamera(m);
  mdbrief::python::bindFeatures(m);
  mdbrief::python::bindGeometry(m);
  mdbrief::python::bindMatching(m);
  mdbrief::python::bindMatchRefinement(m);
  mdbrief::python::bindOptions(m);
  mdbrief::python::bindPatterns(m);
  mdbrief::python::bindPresets(m);
  mdbrief::python::bindSimdLevel(m);
  mdbrief::python::bindVocabulary(m);
  mdbrief::python::bindDatabase(m);
  mdbrief::python::finishClasses(m);
}
