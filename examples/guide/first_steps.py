#!/usr/bin/python3
"""The user guide's Python walk-through (docs/guide/README.md): load a calibration, extract,
match brute force and guided, verify, train a test set, and query a vocabulary. The guide shows
the parts between the "[guide:NAME]" and "[guide]" lines; tests/python/test_guide_examples.py
runs the whole, so the guide's code runs and does what it says.

    PYTHONPATH=build/python /usr/bin/python3 examples/guide/first_steps.py CALIBRATION VOCABULARY WORK_DIR
"""
import pathlib
import sys

import cv2
import numpy as np

# [guide:import]
import mdbrief
# [guide]


def textured_image(size, seed):
    """Random discs and bars, blurred a little as a lens would; the same picture every run."""
    width, height = size
    rng = np.random.default_rng(seed)
    image = np.full((height, width), 128, np.uint8)
    for i in range(900):
        x, y = (int(v) for v in rng.integers([0, 0], [width, height]))
        shade = int(rng.integers(0, 256))
        if i % 3 == 0:
            cv2.circle(image, (x, y), int(rng.integers(2, 14)), shade, cv2.FILLED, cv2.LINE_AA)
        else:
            dx, dy = (int(v) for v in rng.integers(-20, 21, 2))
            cv2.rectangle(image, (x, y), (x + dx, y + dy), shade, cv2.FILLED, cv2.LINE_AA)
    return cv2.GaussianBlur(image, (0, 0), 1.0)


def rolled(camera, image, degrees):
    """The image with the lens rolled about its axis: an exact rotation about the principal
    point for a radially symmetric lens. Returns the image and the 2 x 3 map of the truth."""
    centre = camera.bearing_to_pixel(np.array([[0.0, 0.0, 1.0]]))[0]
    truth = cv2.getRotationMatrix2D((float(centre[0]), float(centre[1])), degrees, 1.0)
    height, width = image.shape[:2]
    return cv2.warpAffine(image, truth, (width, height), borderValue=128), truth


def check(condition, what):
    if not condition:
        sys.exit(f"first_steps.py: {what}")


def main(calibration_path, vocabulary_path, work):
    work = pathlib.Path(work)
    # [guide:load-camera]
    # Any calibration file mdbrief reads: the project's YAML, OCamCalib's calib_results.txt,
    # Kalibr, basalt, ORB-SLAM3, OpenCV, COLMAP (format=... and camera_id=... pick one).
    camera = mdbrief.load_camera(calibration_path)
    # or mdbrief.Camera("kannala_brandt", 1280, 800, fx=..., ...), or
    # mdbrief.Camera.from_opencv(K, D, (width, height)) from cv2.fisheye.calibrate
    bearings = camera.pixel_to_bearing(np.array([[100.0, 200.0]]))  # (N, 3) unit rays
    # [guide]
    width, height = camera.image_size
    image1 = textured_image((width, height), seed=7)
    image2, truth = rolled(camera, image1, 12.0)

    # [guide:extract]
    features = mdbrief.MdBrief(camera)  # the defaults; every MdBriefOptions field is a keyword
    keypoints1, descriptors1, masks1 = features.detect_and_compute(image1)
    keypoints2, descriptors2, masks2 = features.detect_and_compute(image2)
    # keypoints: cv2.KeyPoint; descriptors and masks: (N, 32) uint8 arrays
    # [guide]

    # [guide:match]
    matches = mdbrief.match(descriptors1, descriptors2, masks1, masks2)  # list of cv2.DMatch
    # [guide]

    # [guide:verify]
    # The second view is an image rotation here, so a homography between the pixels is exact;
    # between two poses of a moving camera fit the model on the bearings ("Geometry").
    points1 = np.float32([keypoints1[m.queryIdx].pt for m in matches])
    points2 = np.float32([keypoints2[m.trainIdx].pt for m in matches])
    homography, inliers = cv2.findHomography(points1, points2, cv2.RANSAC, 2.0)
    # [guide]
    expected = points1 @ truth[:, :2].T + truth[:, 2]
    correct = np.linalg.norm(points2 - expected, axis=1) <= 3.0
    print(f"{len(keypoints1)} and {len(keypoints2)} keypoints, {len(matches)} matches, "
          f"{int(correct.sum())} correct, {int(inliers.sum())} inliers")
    check(len(matches) >= 100, "fewer than 100 matches")
    check(correct.mean() >= 0.9, "fewer than 90 % of the matches correct")
    check(inliers.ravel()[correct].mean() >= 0.9, "the homography keeps fewer than 90 % of the correct matches")

    # [guide:guided]
    # A tracker's next frame: each query searched only near its predicted position (radius 15 px).
    positions = np.float32([k.pt for k in keypoints1])
    predicted = positions @ truth[:, :2].T + truth[:, 2]  # a motion model's (N, 2) prediction
    tracked = mdbrief.match_guided(descriptors1, descriptors2, predicted, keypoints2, (width, height),
                                   masks1, masks2, radius=15)
    # [guide]
    check(len(tracked) >= len(matches), "guided matching found fewer matches than brute force")

    # [guide:geometry]
    # The check on bearings: any lens, beyond 90 degrees of incidence. A turned camera (as here)
    # or a plane: fit_homography; a camera that also moved: fit_essential (rotation, translation
    # of view 2 in view 1); a calibrated pair or odometry: check_known_pose.
    bearings1 = camera.pixel_to_bearing(points1)
    bearings2 = camera.pixel_to_bearing(points2)
    turn = mdbrief.fit_homography(bearings1, bearings2)  # max_angle=0.005 (radians)
    if not turn.ok:
        print("no model:", turn.reason)
    # turn.inliers (bool per match), turn.residuals (radians), turn.model (3x3)
    # [guide]
    print(f"homography on bearings: {turn.inlier_count} of {len(matches)} matches")
    check(turn.ok and turn.inliers[correct].mean() >= 0.9,
          "the bearing homography keeps fewer than 90 % of the correct matches")

    work.mkdir(parents=True, exist_ok=True)
    camchain = work / "camchain.yaml"  # as Kalibr writes it: cam1 11 cm right of cam0
    fisheye = ("  camera_model: pinhole\n  distortion_model: equidistant\n"
               "  distortion_coeffs: [-0.0125, 0.0578, -0.0850, 0.0436]\n"
               "  intrinsics: [461.6, 460.3, 366.3, 249.1]\n  resolution: [752, 480]\n")
    camchain.write_text("cam0:\n" + fisheye + "cam1:\n  T_cn_cnm1:\n  - [1.0, 0.0, 0.0, -0.11]\n"
                        "  - [0.0, 1.0, 0.0, 0.0]\n  - [0.0, 0.0, 1.0, 0.0]\n  - [0.0, 0.0, 0.0, 1.0]\n" + fisheye)
    for name, x in (("cam0", 0.0), ("cam1", 0.11)):  # the same rig in EuRoC's ASL layout
        (work / name).mkdir(exist_ok=True)
        (work / name / "sensor.yaml").write_text(
            f"sensor_type: camera\nT_BS:\n  cols: 4\n  rows: 4\n  data: [1, 0, 0, {x}, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\n"
            "camera_model: pinhole\nintrinsics: [461.6, 460.3, 366.3, 249.1]\nresolution: [752, 480]\n"
            "distortion_model: equidistant\ndistortion_coefficients: [-0.0125, 0.0578, -0.0850, 0.0436]\n")
    # [guide:rig]
    rig = mdbrief.load_rig(str(camchain))  # a Kalibr camchain
    left, right = rig.camera("cam0"), rig.camera("cam1")
    rotation, translation = rig.relative_pose("cam0", "cam1")  # x_cam0 = R @ x_cam1 + t
    euroc = mdbrief.load_rig([str(work / "cam0/sensor.yaml"), str(work / "cam1/sensor.yaml")])  # named by folder
    euroc_rotation, euroc_translation = euroc.relative_pose("cam0", "cam1")
    # ... then with the matches' bearings of the left and right images:
    #   labels = mdbrief.check_known_pose(bearings_left, bearings_right, rotation, translation)
    # [guide]
    check(np.allclose(euroc_rotation, rotation) and np.allclose(euroc_translation, translation, atol=1e-12),
          "the ASL layout's pose differs from the camchain's")
    points = np.random.default_rng(3).uniform([-2, -1.5, 1], [2, 1.5, 5], (200, 3))  # cam0's frame
    pixels_left = left.bearing_to_pixel(points)
    pixels_right = right.bearing_to_pixel((points - translation) @ rotation)  # R^T (x - t), row-wise
    seen = np.isfinite(pixels_left).all(axis=1) & np.isfinite(pixels_right).all(axis=1)
    bearings_left = left.pixel_to_bearing(pixels_left[seen])
    bearings_right = right.pixel_to_bearing(pixels_right[seen])
    labels = mdbrief.check_known_pose(bearings_left, bearings_right, rotation, translation)
    shuffled = mdbrief.check_known_pose(bearings_left, np.roll(bearings_right, 7, axis=0), rotation, translation)
    print(f"rig: {int(labels.inlier_count)} of {int(seen.sum())} true matches right, "
          f"{int((~shuffled.inliers).sum())} shuffled ones wrong")
    check(seen.sum() > 100 and labels.inliers.all(), "a true match of the rig was labelled wrong")
    check((~shuffled.inliers).mean() >= 0.95, "fewer than 95 % of the shuffled matches labelled wrong")

    # [guide:presets]
    wide = mdbrief.MdBrief(camera, preset="matching", nfeatures=1500)  # 512 bits
    # ... then mdbrief.match(d1, d2, m1, m2, preset="matching", ratio=0.7)
    # mdbrief.presets() lists the presets; help(mdbrief.MdBrief) every option with its range
    # [guide]
    check(wide.detect_and_compute(image1)[1].shape[1] == 64, "the matching preset does not give 512 bits")

    images = work / "training_images"
    images.mkdir(parents=True, exist_ok=True)
    for seed in range(4):
        cv2.imwrite(str(images / f"photo{seed}.png"), textured_image((640, 480), seed=100 + seed))
    # [guide:train]
    # A test set learned from your own images (the photos of a folder), then used like a shipped one.
    tests = mdbrief.train(images=images, patches=800, tests=64, seed=3, name="my_tests_64")
    tests.save(work / "my_tests_64.json")  # the trainer's JSON: mdbrief.load_pattern(path) reads it
    own = mdbrief.MdBrief(camera, pattern=tests, bits=64)
    # [guide]
    check(len(tests) == 64, "the trained set does not have 64 tests")
    check(own.detect_and_compute(image1)[1].shape[1] == 8, "the trained set does not give 64 bits")

    places = [textured_image((width, height), seed) for seed in range(1, 6)]
    revisit, _ = rolled(camera, places[2], 8.0)
    # [guide:vocabulary]
    vocabulary = mdbrief.Vocabulary.load(vocabulary_path)  # trained on the same features
    database = mdbrief.Database(vocabulary)
    for image in places:  # entries 0, 1, 2, ... in this order
        _, d, m = features.detect_and_compute(image)
        database.add(d, m)
    _, d, m = features.detect_and_compute(revisit)
    best = database.query(d, m, max_results=3)  # [(entry, score), ...], best first
    # [guide]
    print("query:", best)
    check(best and best[0][0] == 2, "the revisit did not find its place first")


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit("usage: first_steps.py CALIBRATION VOCABULARY WORK_DIR")
    main(*sys.argv[1:])
