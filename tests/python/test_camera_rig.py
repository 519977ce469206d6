"""Rigs (mdbrief.load_rig) and the calibration files SLAM tools write: EuRoC / Kimera
sensor.yaml, OpenCV's K and D alone, and the relative pose between any two cameras of a rig."""
import numpy as np
import pytest

import mdbrief
from conftest import SOURCE

FORMATS = SOURCE / "tests/data/camera_formats"


def test_euroc_pair_gives_each_camera_and_their_relative_pose():
    cam0, cam1 = FORMATS / "euroc_cam0_sensor.yaml", FORMATS / "euroc_cam1_sensor.yaml"
    rig = mdbrief.load_rig([cam0, cam1])
    assert isinstance(rig, mdbrief.CameraRig)
    assert len(rig) == 2 and rig.format == "euroc"
    assert rig.ids == ["euroc_cam0_sensor", "euroc_cam1_sensor"]  # the files' stems
    assert [c.model for c in rig.cameras] == ["kannala_brandt", "radtan"]
    assert rig.camera(0).to_yaml() == mdbrief.load_camera(cam0).to_yaml()
    R, t = rig.relative_pose(0, 1)
    assert R.shape == (3, 3) and t.shape == (3,)
    np.testing.assert_allclose(R, np.eye(3), atol=1e-12)
    # x_0 = R @ x_1 + t: camera 1 is 11 cm to the right of camera 0.
    np.testing.assert_allclose(t, [0.11, 0.0, 0.0], atol=1e-12)
    R10, t10 = rig.relative_pose("euroc_cam1_sensor", "euroc_cam0_sensor")
    np.testing.assert_allclose(t10, [-0.11, 0.0, 0.0], atol=1e-12)


def test_kalibr_and_basalt_rigs_by_id_and_index():
    kalibr = mdbrief.load_rig(FORMATS / "kalibr_camchain.yaml")
    assert kalibr.ids == ["cam0", "cam1", "cam2", "cam3", "cam4"]
    R, t = kalibr.relative_pose("cam0", "cam1")
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
    assert abs(t[0] - 0.110) < 1e-3
    assert kalibr.has_relative_pose(0, 1) and not kalibr.has_relative_pose(0, 2)
    with pytest.raises(ValueError, match="camera 'cam2' has no extrinsics"):
        kalibr.relative_pose("cam0", "cam2")
    with pytest.raises(KeyError, match="cam9"):
        kalibr.camera("cam9")
    with pytest.raises(IndexError):
        kalibr.camera(5)
    basalt = mdbrief.load_rig(str(FORMATS / "basalt_calib.json"))
    assert basalt.ids == ["0", "1", "2", "3", "4"]
    assert abs(np.linalg.norm(basalt.relative_pose(0, 1)[1]) - 0.110) < 1e-3


def test_sensor_files_and_bare_k_d_files_load_as_cameras():
    assert mdbrief.load_camera(FORMATS / "kimera_omni_sensor.yaml").model == "ocam"
    kd = FORMATS / "opencv_kd_fisheye.yaml"
    with pytest.raises(ValueError, match=r"image_size=\(w, h\)"):
        mdbrief.load_camera(kd)
    with pytest.raises(ValueError, match="opencv_model="):
        mdbrief.load_camera(kd, image_size=(752, 480))
    camera = mdbrief.load_camera(kd, image_size=(752, 480), opencv_model="fisheye")
    assert camera.model == "kannala_brandt" and camera.image_size == (752, 480)
    with pytest.raises(ValueError, match="image_size"):
        mdbrief.load_camera(kd, image_size=(0, 480))
    with pytest.raises(ValueError, match="opencv_model"):
        mdbrief.load_camera(kd, image_size=(752, 480), opencv_model="fish")


def test_bad_sensor_files_name_the_key(tmp_path):
    sensor = tmp_path / "sensor.yaml"
    sensor.write_text("sensor_type: camera\nresolution: [752, 480]\ncamera_model: pinhole\n"
                      "intrinsics: [461, 460, 366, 249]\n")
    with pytest.raises(ValueError, match="key 'distortion_model' is missing"):
        mdbrief.load_camera(sensor)
    unknown = tmp_path / "unknown.yaml"
    unknown.write_text("a: 1\n")
    with pytest.raises(ValueError, match='Python format="NAME"'):
        mdbrief.load_camera(unknown)
    with pytest.raises(ValueError, match="holds 5 cameras"):
        mdbrief.load_rig([FORMATS / "kalibr_camchain.yaml"])
    with pytest.raises(FileNotFoundError):
        mdbrief.load_rig([tmp_path / "missing.yaml"])
