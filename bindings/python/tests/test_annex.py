"""`import annex` on the bundled samples: versions, PCD frames as numpy arrays, scans,
specs, matches and a session over the recorded tabletop sequence. Run by ctest
(test_python) with the built module on PYTHONPATH; real Kinect scans skip when
../shared is absent."""
import os
import pathlib

import numpy as np
import pytest

import annex

SOURCE = pathlib.Path(os.environ["ANNEX_SOURCE_DIR"])
SHARED = pathlib.Path(os.environ.get("ANNEX_SHARED_DIR", SOURCE.parent / "shared"))
RECORDING = SOURCE / "samples" / "recordings" / "tabletop"
STUDY = SOURCE / "samples" / "specs" / "study.haptic"
MILK = SOURCE / "samples" / "real" / "milk_cartoon_all_small_clorox.pcd"


def frames():
    return sorted(RECORDING.glob("frame_*.pcd"))


def test_version_is_the_projects():
    assert annex.__version__ == os.environ["ANNEX_EXPECTED_VERSION"]


def test_load_pcd_gives_an_organized_float32_array():
    points = annex.load_pcd(str(frames()[0]))
    assert points.dtype == np.float32
    assert points.shape == (480, 640, 3)  # the VGA recording
    valid = np.isfinite(points[..., 2])
    assert valid.mean() > 0.5
    assert 0.3 < np.median(points[..., 2][valid]) < 3.0  # metres


def test_load_pcd_error_names_the_file(tmp_path):
    # A missing file in pytest's own temporary folder (never one another run creates).
    with pytest.raises(annex.Error, match="no_such_frame.pcd"):
        annex.load_pcd(str(tmp_path / "no_such_frame.pcd"))


def test_scan_finds_the_three_props():
    objects = annex.scan(annex.load_pcd(str(frames()[0])))
    # The recording's props: a sphere (r 5.2 cm), a cylinder (r 5.6, h 19.3 cm) and a
    # torus (R 6.3, r 2.2 cm), samples/recordings/README.md.
    # The scan also reports a partial object cut by the image border (`unknown`).
    by_shape = {o.shape: o for o in objects if o.shape != "unknown"}
    assert sorted(by_shape) == ["cylinder", "sphere", "torus"]
    assert [o.id for o in objects] == ["p%d" % (k + 1) for k in range(len(objects))]
    assert by_shape["sphere"].dims["radius"] == pytest.approx(0.052, abs=0.006)
    assert by_shape["cylinder"].dims["radius"] == pytest.approx(0.056, abs=0.006)
    assert by_shape["cylinder"].dims["height"] == pytest.approx(0.193, abs=0.02)
    for o in by_shape.values():
        assert o.on_object == ""  # each stands on the table, none on another
        assert o.center.shape == (3,)
        assert 0.3 < o.center[2] < 2.0
        assert o.primitives[0].shape == o.shape


def test_scan_rejects_bad_arrays_and_configs(tmp_path):
    with pytest.raises(ValueError, match=r"\(H, W, 3\)"):
        annex.scan(np.zeros((10, 3), dtype=np.float32))
    with pytest.raises(annex.Error, match="no plane|support|valid"):
        annex.scan(np.full((48, 64, 3), np.nan, dtype=np.float32))
    with pytest.raises(annex.Error, match="nope.conf"):
        annex.scan(np.zeros((4, 4, 3), dtype=np.float32), config=str(tmp_path / "nope.conf"))


def test_a_config_names_the_depth_camera(tmp_path):
    # A RealSense's noise model from a scan config; an unknown camera names the line.
    conf = tmp_path / "stereo.conf"
    conf.write_text("depth_noise stereo\nsupports s9\n")
    with pytest.raises(annex.Error, match="no support 's9'"):
        annex.scan(annex.load_pcd(str(MILK)), config=str(conf))
    spec = annex.read_spec(str(STUDY))
    assert annex.Session(spec, config=str(conf)) is not None
    conf.write_text("depth_noise lidar\n")
    with pytest.raises(annex.Error, match=r"stereo.conf:1:13: error: .*kinect, stereo, tof"):
        annex.scan(annex.load_pcd(str(MILK)), config=str(conf))


def test_specs_read_and_errors_carry_line_and_column():
    spec = annex.read_spec(str(STUDY))
    assert "champagne_bottle" in spec.names
    assert len(spec) == len(spec.names)
    with pytest.raises(annex.Error, match=r"^cup.haptic:4:\d+: error"):
        annex.parse_spec(
            "annex-haptic 1\nobject cup\n  primitive body cylinder\n    priority heavy\n  end\nend\n",
            "cup.haptic")


def test_spec_gives_each_objects_model_scale():
    spec = annex.parse_spec(
        "annex-haptic 1\nobject duck\n  mesh duck.dae\n  model_scale 0.078\n"
        "  primitive body sphere\n    radius 0.05\n  end\nend\nobject cup\n"
        "  primitive body cylinder\n    radius 0.04\n    height 0.1\n  end\nend\n", "units.haptic")
    assert spec.model_scales == pytest.approx([0.078, 1.0])


def test_match_puts_the_study_objects_on_the_props():
    spec = annex.read_spec(str(STUDY))
    objects = annex.scan(annex.load_pcd(str(frames()[0])))
    shape_of = {o.id: o.shape for o in objects}
    matches = {m.virtual: m for m in annex.match(spec, objects)}
    assert len(matches) == len(spec)
    # As `annex-runtime run` annexes them (samples/recordings/README.md).
    assert shape_of[matches["champagne_bottle"].physical] == "cylinder"
    assert shape_of[matches["lamp"].physical] == "sphere"
    # The mug stays virtual: its best prop votes under its min_vote (study.haptic).
    assert matches["mug"].physical is None
    assert matches["lamp"].vote > 0
    assert matches["lamp"].explanation.startswith("lamp x ")
    unmatched = [m for m in matches.values() if m.physical is None]
    assert len(unmatched) == len(spec) - 2


def test_session_tracks_the_recording():
    spec = annex.read_spec(str(STUDY))
    session = annex.Session(spec, scan_every=5)
    first = None
    for k, path in enumerate(frames()):
        objects = session.process(annex.load_pcd(str(path)))
        if k == 0:
            first = {o.virtual: o.physical for o in objects}
            assert sorted(first) == ["champagne_bottle", "lamp"]
        assert {o.virtual: o.physical for o in objects} == first
        for o in objects:
            assert o.state in ("tracking", "reinit")
            assert o.position.shape == (3,) and o.rotation.shape == (4,)
            assert np.linalg.norm(o.rotation) == pytest.approx(1.0)
            assert o.matrix.shape == (4, 4)
            # The matrix maps the model origin to the pose's position.
            assert np.allclose(o.matrix[:3, 3], o.position)
            assert np.array_equal(o.matrix[3], [0.0, 0.0, 0.0, 1.0])
            assert 0.0 <= o.confidence <= 1.0
    assert len(frames()) == 4


def test_background_session_applies_scans_a_frame_later():
    spec = annex.read_spec(str(STUDY))
    session = annex.Session(spec, background=True)
    points = [annex.load_pcd(str(p)) for p in frames()[:3]]
    assert session.process(points[0]) == []
    session.wait_for_scan()
    objects = session.process(points[1])
    assert sorted(o.virtual for o in objects) == ["champagne_bottle", "lamp"]
    assert all(o.matched_frame == 1 for o in objects)


KEYBOARD = """annex-haptic 1
object keyboard
  primitive keys plane
    size_x 0.50
    size_y 0.12
  end
end
"""


def test_session_lays_a_virtual_panel_on_the_table():
    spec = annex.parse_spec(KEYBOARD, "keyboard.haptic")
    points = annex.load_pcd(str(frames()[0]))
    # The scan's flat surfaces come after its objects only when asked for; the table's
    # free rectangle in reach is one plane, and the keyboard matches it only then.
    objects = annex.scan(points)
    scanned = annex.scan(points, surfaces=True)
    assert [o.id for o in scanned[: len(objects)]] == [o.id for o in objects]
    assert all(o.shape != "plane" for o in objects)
    free = {o.id: o for o in scanned[len(objects):]}["s1.free"]
    assert free.shape == "plane" and len(free.primitives) == 1
    table = free.primitives[0]
    assert table.dims["size_x"] >= table.dims["size_y"] >= 0.12
    assert np.dot(table.x_axis, table.axis) == pytest.approx(0.0, abs=1e-6)
    assert annex.match(spec, scanned)[0].physical == "s1.free"
    assert annex.match(spec, objects)[0].physical is None

    session = annex.Session(spec, scan_every=2)
    for k, path in enumerate(frames()):
        points = annex.load_pcd(str(path))
        annexed = session.process(points)
        assert [(o.virtual, o.physical) for o in annexed] == [("keyboard", "s1.free")], k
        panel = annexed[0]
        assert panel.state in ("tracking", "held")
        # The matrix is the rotation times the per-axis scale: its columns are the
        # panel's axes, size_x along the surface's longer side, +Z the table's normal,
        # stretched in its plane only.
        assert panel.scale[2] == pytest.approx(1.0)
        axes = panel.matrix[:3, :3] / panel.scale
        assert np.allclose(axes.T @ axes, np.eye(3), atol=1e-6)
        if k == 0:
            assert np.linalg.norm(panel.position - table.center) < 0.01
            # Stretched to the surface within the spec's default scale limits [0.5, 2].
            size = np.array([table.dims["size_x"], table.dims["size_y"]])
            assert np.allclose(panel.scale[:2], np.clip(size / [0.50, 0.12], 0.5, 2.0), rtol=0.02)
            assert abs(np.dot(axes[:, 0], table.x_axis)) > 0.99
        # Carried by the camera's motion, it stays on this frame's table.
        here = {o.id: o for o in annex.scan(points, surfaces=True)}["s1.free"].primitives[0]
        assert np.dot(axes[:, 2], here.axis) > 0.99, k
        assert abs(np.dot(panel.position - here.center, here.axis)) < 0.01, k


def test_session_params_are_checked():
    spec = annex.read_spec(str(STUDY))
    with pytest.raises(annex.Error, match="SessionParams.scan_every must be at least 1, got 0"):
        annex.Session(spec, scan_every=0)


def test_real_kinect_frame():
    path = SHARED / "data" / "real" / "milk_cartoon_all_small_clorox.pcd"
    if not path.exists():
        pytest.skip(f"{path} not found (../shared is not checked out)")
    points = annex.load_pcd(str(path))
    assert points.shape == (480, 640, 3)
    objects = annex.scan(points)
    assert len(objects) >= 3
    assert "box" in {o.shape for o in objects}  # the milk carton
