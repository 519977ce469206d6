"""mdbrief: distorted binary descriptors for calibrated wide-angle and fisheye cameras.

    import cv2, mdbrief
    camera = mdbrief.load_camera("/usr/local/share/mdbrief/cameras/lafida_fisheye0.yaml")
    features = mdbrief.MdBrief(camera)                  # preset="tracking": the library's defaults
    image1, image2 = cv2.imread("a.png"), cv2.imread("b.png")
    kp1, d1, m1 = features.detect_and_compute(image1)
    kp2, d2, m2 = features.detect_and_compute(image2)
    matches = mdbrief.match(d1, d2, m1, m2)             # the preset's ratio test and mutual check
    # Sub-pixel points in image2, for views that did not turn (refined.points_b, .sigma_px, .ok).
    refined = mdbrief.refine_matches(features, image1, kp1, image2, kp2, matches)
    # A tracker's next frame: search only near where the motion model predicts each keypoint.
    tracked = mdbrief.match_guided(d1, d2, predicted, kp2, (width, height), m1, m2, radius=15)
    # Which matches are right: the relative pose of a general scene, on bearings (any lens).
    a = camera.pixel_to_bearing(np.array([kp1[m.queryIdx].pt for m in matches]))
    b = camera.pixel_to_bearing(np.array([kp2[m.trainIdx].pt for m in matches]))
    fit = mdbrief.fit_essential(a, b)                   # fit.inliers, fit.rotation, fit.residuals
    vocabulary = mdbrief.Vocabulary.load("vocabulary.mdbvoc")   # place recognition (docs/vocabulary.md)
    database = mdbrief.Database(vocabulary)
    database.add(d1, m1)
    best = database.query(d2, m2, max_results=5)        # [(entry, score), ...], best first

The user guide (docs/guide/README.md in the source tree) walks through each task; the figures
behind the defaults are in docs/RESULTS.md.

Keypoints are cv2.KeyPoint and matches cv2.DMatch objects, so cv2.drawKeypoints,
cv2.drawMatches and cv2.BFMatcher(cv2.NORM_HAMMING) take them unchanged. The C++ work runs
without the GIL (but a Database's index, which adding changes, is used with it held).
"""
# Imported first so that a missing OpenCV module fails here (the keypoint and match types the
# module returns are cv2's); private, so the package's namespace holds only its own names.
import cv2 as _cv2  # noqa: F401

from ._mdbrief import __version__  # noqa: F401
from ._mdbrief import (Camera, CameraRig, ComparisonSet, Database, MdBrief, RefinedMatches, TestSet, TwoViewResult,
                       Vocabulary, camera_models, check_known_pose, default_pattern, fit_essential, fit_homography,
                       limit_simd_level, load_camera, load_pattern, load_rig, match, match_guided, option_fields,
                       patterns, pixels_per_radian, presets, refine_matches, simd_level, supported_simd_level,
                       supported_simd_levels, train)

# TestSet: ComparisonSet's name in 0.2, the same class object (deprecated).
__all__ = ["Camera", "CameraRig", "ComparisonSet", "Database", "MdBrief", "RefinedMatches", "TestSet", "TwoViewResult",
           "Vocabulary", "camera_models", "check_known_pose", "default_pattern", "fit_essential", "fit_homography",
           "limit_simd_level", "load_camera", "load_pattern", "load_rig", "match", "match_guided", "option_fields",
           "patterns", "pixels_per_radian", "presets", "refine_matches", "simd_level", "supported_simd_level",
           "supported_simd_levels", "train"]
