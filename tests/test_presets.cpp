// The named settings of mdbrief/api/presets.hpp: tracking is exactly what create() and MatchOptions{}
// give, every preset passes validate(), and names parse both ways.
#include <gtest/gtest.h>

#include "mdbrief/api/presets.hpp"

namespace mdbrief {
namespace {

TEST(Presets, TrackingIsTheDefaultsAndEveryPresetIsValid) {
  const PresetSettings tracking = presetSettings(Preset::Tracking);
  // The field tables compare every option.
  for (const auto& f : mdBriefOptionFields()) EXPECT_EQ(f.get(tracking.features), f.get(MdBriefOptions{})) << f.member;
  for (const auto& f : matchOptionFields()) EXPECT_EQ(f.get(tracking.matching), f.get(MatchOptions{})) << f.member;
  for (const std::string& name : namesOf(kPresetNames)) {
    const PresetSettings s = presetSettings(parsePreset(name));
    EXPECT_NO_THROW(validate(s.features)) << name;
    EXPECT_NO_THROW(validate(s.matching)) << name;
    EXPECT_EQ(toString(parsePreset(name)), name);
  }
  EXPECT_EQ(presetSettings(Preset::Matching).features.descriptor.bits, 512);
  const PresetSettings paper = presetSettings(Preset::Paper);
  EXPECT_EQ(paper.features.detector.method, DetectorMethod::ModOrb);
  EXPECT_EQ(paper.features.descriptor.form, DistortionForm::Paper);
  EXPECT_FALSE(paper.matching.ratio);
  EXPECT_FALSE(paper.matching.crossCheck);
}

TEST(Presets, AnUnknownNameListsThePresets) {
  try {
    parsePreset("fast");
    FAIL() << "'fast' is not a preset";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "preset 'fast' is not one of: tracking, matching, paper");
  }
}

}  // namespace
}  // namespace mdbrief
