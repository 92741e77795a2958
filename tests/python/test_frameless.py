"""The `frameless` Python module (issue 29; docs/python.md): renders as numpy arrays, an Engine
that follows the camera and materials, per-pixel state, and errors as ValueError with the command
line's one-line message. Run by tools/test.sh (pytest; FRAMELESS_PYTHON_DIR names the module's
folder in the build)."""
import threading
import time

import numpy as np
import pytest

import frameless

BALL = """{"camera": {"eye": [0, 0, 4], "look": [0, 0, 0]},
  "lights": [{"type": "point", "position": [2, 3, 4], "color": 1}], "ambient": {"type": "none"},
  "materials": {"ball": {"class": "diffuse", "kd": [0.8, 0.2, 0.1]}},
  "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "ball"}]}"""


def test_render_gives_an_h_w_3_float32_array():
    img = frameless.render("default", size=(48, 32), spp=2)
    assert img.shape == (32, 48, 3)
    assert img.dtype == np.float32
    assert np.isfinite(img).all()
    assert img.mean() > 0.01


def test_a_scene_from_json_renders_its_ball_and_moves_its_camera():
    ball = frameless.Scene.from_json(BALL)
    assert ball.info["materials"] == ["ball"]
    img = frameless.render(ball, size=(32, 32), spp=1)
    assert img[16, 16, 0] > 3 * img[16, 16, 2]
    assert img[0, 0].sum() == 0
    away = frameless.render(ball, size=(32, 32), spp=1, look=(0, 0, 8))
    assert away.sum() == 0


def test_bad_input_raises_value_error_with_one_line():
    with pytest.raises(ValueError) as e:
        frameless.render("/nonexistent/scene.json")
    assert "/nonexistent/scene.json" in str(e.value) and "\n" not in str(e.value)
    with pytest.raises(ValueError, match="objects"):
        frameless.Scene.from_json('{"objects": [{"type": "sphere", "radius": -1}]}')
    with pytest.raises(ValueError, match="mode"):
        frameless.Engine("default", mode="sideways")
    with pytest.raises(ValueError, match="size"):
        frameless.render("default", size=(0, 10))


def test_an_engine_follows_materials_and_camera_and_shows_its_state():
    with frameless.Engine(frameless.Scene.from_json(BALL), size=(32, 32), threads=2,
                          deterministic=True, samples_per_tick=4096) as e:
        e.advance(4)
        assert e.image()[16, 16, 0] > 0.1
        count = e.state("count")
        assert count.shape == (32, 32) and count[16, 16] > 0
        with pytest.raises(ValueError, match="unknown layer"):
            e.state("colour")
        e.set_material_color("ball", (0.1, 0.2, 0.8))
        e.advance(8)
        blue = e.image()
        assert blue[16, 16, 2] > blue[16, 16, 0]
        e.set_camera(eye=(0, 0, 4), look=(3, 0, 0), fov=30)
        e.advance(8)
        assert e.image()[16, 16].sum() == 0
        assert e.stats()["samples"] > 20000
    assert not e.running


def test_rendering_and_running_engines_leave_python_free():
    # A render on another thread releases the GIL: this thread keeps counting meanwhile.
    out = []
    t = threading.Thread(target=lambda: out.append(frameless.render("default", size=(320, 240), spp=16)))
    t.start()
    counted = 0
    while t.is_alive():
        counted += 1
    t.join()
    assert out[0].shape == (240, 320, 3)
    assert counted > 10000
    # An engine renders on its own threads while Python sleeps.
    e = frameless.Engine("default", size=(64, 48), threads=2)
    time.sleep(0.4)
    stats = e.stats()
    e.stop()
    assert stats["samples"] > 0 and stats["display_ticks"] > 0


def test_capture_and_update_statistics(tmp_path):
    info = frameless.capture("default", str(tmp_path / "cap"), duration=0.3, refresh_hz=10, size=(48, 32),
                             deterministic=True, orbit=20, layers=["age"])
    assert info["frames"] == 3
    assert (tmp_path / "cap" / "frame_00002.exr").exists()
    with pytest.raises(ValueError, match="duration"):
        frameless.capture("default", str(tmp_path / "bad"), duration=-1)
    st = frameless.update_statistics("default", threads=2)
    assert st["updates_min"] == st["updates_max"] == 4
    assert st["staleness_measured"] and st["t100_sweeps"] <= st["bound_sweeps"] + 1e-9
    assert len(st["thread_pixels"]) == 2 and st["balanced"]


def test_moving_objects_and_instances():
    scene = frameless.Scene.from_json("""{"camera": {"eye": [0, 0, 4], "look": [0, 0, 0]},
      "ambient": {"type": "constant", "color": 1},
      "materials": {"m": {"class": "diffuse", "kd": [0.9, 0.1, 0.1]}, "q": {"class": "diffuse", "kd": [0.1, 0.1, 0.9]}},
      "meshes": {"quad": {"type": "triangles", "vertices": [[-0.3,-0.3,0],[0.3,-0.3,0],[0.3,0.3,0],[-0.3,0.3,0]],
                          "indices": [[0,1,2],[0,2,3]], "material": "q"}},
      "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.3, "material": "m", "dynamic": true},
                  {"type": "instance", "mesh": "quad", "transform": {"translate": [0, 0, -1]}}]}""")
    assert scene.info["moving_objects"] == 1 and scene.info["instances"] == 1
    with frameless.Engine(scene, size=(32, 32), threads=1, deterministic=True, samples_per_tick=2048) as e:
        e.advance(6)
        assert e.image()[16, 16, 0] > 0.5
        e.set_object_position(0, (5, 0, 0))
        e.advance(6)
        assert e.image()[16, 16, 2] > 0.5
        e.set_instance_transform(0, np.array([[1, 0, 0, 9], [0, 1, 0, 0], [0, 0, 1, -1]]))
        e.advance(6)
        assert e.image()[16, 16].sum() == 0
        with pytest.raises(ValueError, match="instance"):
            e.set_instance_transform(3, np.eye(4))


def test_the_office_finds_its_plug_in_shaders_from_python():
    office = frameless.Scene.load("office")
    assert office.info["lightfields"] == 2 and office.info["volumes"] == 1
    img = frameless.render(office, size=(48, 30), spp=1)
    assert np.isfinite(img).all() and img.mean() > 0.05
