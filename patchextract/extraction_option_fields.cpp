// The field tables of the patch extraction's options (mdbrief/base/option_fields.hpp), shared by
// mdbrief-patchextract, mdbrief-train and Python's mdbrief.train().
#include <cstdint>
#include <limits>

#include "patchextract/patch_extraction.hpp"
#include "patchextract/view_change.hpp"

namespace mdbrief::train {

using R = FieldRange;

const OptionTable<ViewChangeOptions>& viewChangeOptionFields() {
  using O = ViewChangeOptions;
  static const OptionTable<O> table = {
      // Beyond 70 degrees a plane's texture is too foreshortened for any detector to find it again.
      realField<O>("maxTiltDeg", "", "view_tilt", "--view-tilt", "view change: max out-of-plane rotation (deg)",
                   R::closed(0, 70), [](auto& o) -> auto& { return o.maxTiltDeg; }),
      realField<O>("maxRollDeg", "", "view_roll", "--view-roll", "view change: max in-plane rotation (deg)",
                   R::closed(0, 180), [](auto& o) -> auto& { return o.maxRollDeg; }),
      realField<O>("maxZoom", "", "view_zoom", "--view-zoom", "view change: max zoom factor (either way)",
                   R::closed(1, 3), [](auto& o) -> auto& { return o.maxZoom; }),
      realField<O>("maxBlurSigma", "", "view_blur", "--view-blur", "view change: max Gaussian blur sigma (px)",
                   R::closed(0, 5), [](auto& o) -> auto& { return o.maxBlurSigma; }),
      realField<O>("maxNoiseSigma", "", "view_noise", "--view-noise",
                   "view change: max noise sigma (grey levels)", R::closed(0, 50),
                   [](auto& o) -> auto& { return o.maxNoiseSigma; }),
  };
  return table;
}

void validate(const ViewChangeOptions& options) {
  validateFields(viewChangeOptionFields(), options, "ViewChangeOptions");
}

const OptionTable<ExtractionOptions>& extractionOptionFields() {
  using O = ExtractionOptions;
  static const OptionTable<O> table = [] {
    OptionTable<O> t = {
        textListField<O>("imageDirs", "", "images", "--images", "image folders (searched recursively)",
                         [](auto& o) -> auto& { return o.imageDirs; }),
        choiceField<O>("detector", "", "detector", "--detector", "detector of the keypoints patches are taken at",
                       kDetectorKindNames, [](auto& o) -> auto& { return o.detector; }),
        textField<O>("cameraPath", "", "camera", "--camera",
                     "calibration YAML: patches on the tangent plane (fisheye)",
                     [](auto& o) -> auto& { return o.cameraPath; }),
        choiceField<O>("cameraFormat", "", "camera_format", "--camera-format",
                       "format of the calibration file (auto: recognised from the content)", kCameraFormatNames,
                       [](auto& o) -> auto& { return o.cameraFormat; }),
        textField<O>("cameraId", "", "camera_id", "--camera-id",
                     "the camera of a calibration file that holds several (Kalibr cam0, cam1, ...; basalt's index; "
                     "ORB-SLAM3 1 or 2; COLMAP's CAMERA_ID)",
                     [](auto& o) -> auto& { return o.cameraId; }),
        // The trainer's bit matrix grows by 46 KiB per patch (one bit per candidate test):
        // 200,000 patches hold 9 GiB.
        integerField<O>("patches", "", "patches", "--patches", "patch budget", R::closed(1, 200000),
                        [](auto& o) -> auto& { return o.patches; }),
        integerField<O>("seed", "", "seed", "--seed", "seed of the patch choice",
                        R::closed(0, std::numeric_limits<uint32_t>::max()), [](auto& o) -> auto& { return o.seed; }),
        // The detectors reserve room for the whole budget up front (INT_MAX reserved 26 GB in
        // OpenCV's), and the pool's keypoints are held per image.
        integerField<O>("keypointsPerImage", "", "keypoints_per_image", "--keypoints-per-image",
                        "detector budget per image", R::closed(1, kMaxKeypointsPerImage),
                        [](auto& o) -> auto& { return o.keypointsPerImage; }),
        flagField<O>("renderThroughCamera", "", "render_through_camera", "--render-through-camera",
                     "use each photo as a plane seen through the camera (synthetic fisheye images)",
                     [](auto& o) -> auto& { return o.renderThroughCamera; }),
        integerField<O>("counterparts", "", "counterparts", "--counterparts",
                        "changed views per image: the matching pairs of the stability and separation criteria",
                        R::closed(0, kMaxCounterparts), [](auto& o) -> auto& { return o.counterparts; }),
        // The descriptor's own placement by default; another learns a set for a descriptor run
        // with it.
        choiceField<O>("placement.form", "", "form", "--form", "patches placed as dBRIEF/mdBRIEF with this DistortionForm",
                       kDistortionFormNames, [](auto& o) -> auto& { return o.placement.form; }),
        choiceField<O>("placement.orientation", "", "orientation", "--orientation",
                       "patches oriented as dBRIEF/mdBRIEF with this OrientationSource (keypoint: the detector's angle)",
                       kOrientationSourceNames, [](auto& o) -> auto& { return o.placement.orientation; }),
    };
    appendNested(t, viewChangeOptionFields(), "viewChange", "", [](auto& o) -> auto& { return o.viewChange; });
    return t;
  }();
  return table;
}

void validate(const ExtractionOptions& options) {
  validateFields(extractionOptionFields(), options, "ExtractionOptions");
}

}  // namespace mdbrief::train
