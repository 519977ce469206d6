#pragma once
// The command-line flags of the patch placement (ExtractionOptions::placement), shared by
// mdbrief-patchextract and mdbrief-train so both spell and document them the same way. The
// defaults are the descriptor's own; another value learns a set for a descriptor run with it.
#include <string>

#include <CLI/CLI.hpp>

#include "mdbrief/descriptor.hpp"

namespace mdbrief::train {

struct PlacementFlags {
  std::string form = toString(DescriptorOptions{}.form);
  std::string orientation = toString(DescriptorOptions{}.orientation);
};

inline void addPlacementFlags(CLI::App& app, PlacementFlags& f) {
  app.add_option("--form", f.form, "patches placed as dBRIEF/mdBRIEF with this DistortionForm")
      ->check(CLI::IsMember(namesOf(kDistortionFormNames)))
      ->capture_default_str();
  app.add_option("--orientation", f.orientation,
                 "patches oriented as dBRIEF/mdBRIEF with this OrientationSource (keypoint: the detector's angle)")
      ->check(CLI::IsMember(namesOf(kOrientationSourceNames)))
      ->capture_default_str();
}

// The descriptor options the flags select (the parse has checked the names).
inline DescriptorOptions placementOf(const PlacementFlags& f) {
  DescriptorOptions o;
  o.form = parseDistortionForm(f.form);
  o.orientation = parseOrientationSource(f.orientation);
  return o;
}

}  // namespace mdbrief::train
