#include "mdbrief/api/presets.hpp"

namespace mdbrief {

PresetSettings presetSettings(Preset preset) {
  PresetSettings s;  // tracking: the defaults of both structs
  switch (preset) {
    case Preset::Tracking:
      break;
    case Preset::Matching:
      s.features.descriptor.bits = 512;
      s.matching.ratio = 0.65f;
      break;
    case Preset::Paper: {
      DetectorOptions& d = s.features.detector;
      d.method = DetectorMethod::ModOrb;
      d.pyramid = PyramidOptions{};
      DescriptorOptions& e = s.features.descriptor;
      e.form = DistortionForm::Paper;
      e.maxIncidenceDeg = 80.0;  // the paper's plane degenerates towards 90 degrees
      e.pattern = "orb_perspective_paper_512";
      s.matching = MatchOptions{};
      s.matching.ratio.reset();
      s.matching.crossCheck = false;
      break;
    }
  }
  return s;
}

}  // namespace mdbrief
