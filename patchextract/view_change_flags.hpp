#pragma once
// The command-line flags of the stability data (--counterparts and the view change), shared by
// mdbrief-patchextract and mdbrief-train so both spell and document them the same way.
#include <CLI/CLI.hpp>

#include "patchextract/view_change.hpp"

namespace mdbrief::train {

// counterparts: the views per image (the tools' defaults differ, so the caller sets it and its
// help text).
inline void addViewChangeFlags(CLI::App& app, ViewChangeOptions& v) {
  app.add_option("--view-tilt", v.maxTiltDeg, "view change: max out-of-plane rotation (deg)")->capture_default_str();
  app.add_option("--view-roll", v.maxRollDeg, "view change: max in-plane rotation (deg)")->capture_default_str();
  app.add_option("--view-zoom", v.maxZoom, "view change: max zoom factor (either way)")->capture_default_str();
  app.add_option("--view-blur", v.maxBlurSigma, "view change: max Gaussian blur sigma (px)")->capture_default_str();
  app.add_option("--view-noise", v.maxNoiseSigma, "view change: max noise sigma (grey levels)")->capture_default_str();
}

}  // namespace mdbrief::train
