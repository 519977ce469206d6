#pragma once
// Named settings of the whole pipeline: the features (MdBriefOptions) and the matcher
// (MatchOptions) they were chosen with, on real images with the tracker benchmark
// (docs/RESULTS.md "Real images: what a tracker keeps").
// - tracking: MdBrief::create()'s defaults, MdBriefOptions{} and MatchOptions{}: the most
//   right two-view fits per frame pair at a few milliseconds per frame.
// - matching: 512 bits, more distinctive, for wide baselines and relocalisation, where the
//   descriptor counts more than speed; its ratio 0.65 keeps more matches at about the
//   precision of tracking's 0.55.
// - paper: the paper's pipeline (modORB corners, the paper's plane and its learned criterion,
//   nearest neighbours without a ratio test), to reproduce its experiments.
// Start from a preset and change fields: presetSettings(Preset::Matching).features.detector.nfeatures = 2000.
#include <string>

#include "mdbrief/base/enum_names.hpp"
#include "mdbrief/api/feature2d.hpp"
#include "mdbrief/match/matcher.hpp"

namespace mdbrief {

enum class Preset { Tracking, Matching, Paper };
inline constexpr EnumName<Preset> kPresetNames[] = {
    {Preset::Tracking, "tracking"}, {Preset::Matching, "matching"}, {Preset::Paper, "paper"}};
inline std::string toString(Preset preset) { return nameOf(preset, kPresetNames); }
// Throws std::invalid_argument "preset 'x' is not one of: tracking, matching, paper".
inline Preset parsePreset(const std::string& name) { return parseName(name, kPresetNames, "preset"); }

struct PresetSettings {
  MdBriefOptions features;
  MatchOptions matching;
};

PresetSettings presetSettings(Preset preset);

}  // namespace mdbrief
