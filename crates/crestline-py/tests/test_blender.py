"""The Blender extension (blender/) in headless Blender, the ``bpy`` module: built
by tools/build_blender_extension.sh, installed from its zip with the wheel it
bundles, its operators run on real meshes and compared with the command-line tool,
Blender's camera and a Cycles render. Skipped when ``bpy`` is not importable
(``pip install bpy``: Python 3.11) or, for the comparisons, when the tool is not
built (``cargo build --release``; ``$CRESTLINE_TOOL`` names another build).

The zip is built with the wheel of ``$CRESTLINE_WHEEL`` when set, else by the
script (a maturin build reusing target/). The add-on must run the wheel it
bundles: run these tests where crestline itself is not installed (as .ci/run does). ``python test_blender.py PICTURE.png``
renders the documentation's picture."""

import atexit
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import zipfile
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

# Blender's user folders (extensions, preferences) in a folder of this run, set
# before Blender starts.
USER = tempfile.mkdtemp(prefix="crestline-blender-")
os.environ["BLENDER_USER_RESOURCES"] = USER
atexit.register(shutil.rmtree, USER, True)

try:
    import bpy
    from bpy_extras.object_utils import world_to_camera_view
except ImportError as error:
    pytest.skip(f"bpy is not importable ({error}); pip install bpy (Python 3.11)", allow_module_level=True)

import tomllib  # Python 3.11, as bpy

ROOT = Path(__file__).resolve().parents[3]
TOOL = Path(os.environ.get("CRESTLINE_TOOL", ROOT / "target" / "release" / "crestline"))
BUNNY = ROOT / "meshes" / "bunny.obj"
SMALL_BUNNY = ROOT / "meshes" / "bunny_small.obj"
SVG = "{http://www.w3.org/2000/svg}"


@pytest.fixture(scope="module")
def extension():
    """The extension's zip, built and installed (:func:`installed_extension`)."""
    return installed_extension()


def installed_extension():
    """The extension's zip, built by the script and installed into Blender with
    its add-on enabled; the wheel it bundles installed in Blender's site-packages."""
    command = [str(ROOT / "tools" / "build_blender_extension.sh")]
    if os.environ.get("CRESTLINE_WHEEL"):
        command += ["--wheel", os.environ["CRESTLINE_WHEEL"]]
    environment = dict(os.environ, PYTHON=sys.executable)
    built = subprocess.run(command, cwd=ROOT, check=True, capture_output=True, text=True, env=environment)
    archive = Path(built.stdout.strip().splitlines()[-1])
    bpy.ops.extensions.package_install_files(filepath=str(archive), repo="user_default", enable_on_install=True)
    assert hasattr(bpy.ops.object, "crestline_feature_lines") and hasattr(bpy.ops.crestline, "export_svg")
    installed = list(Path(USER).rglob("site-packages/crestline/__init__.py"))
    assert installed, "the bundled wheel was not installed"
    # The add-on runs the bundled package (the environment has no other crestline:
    # one installed beside bpy would come first on the path).
    import crestline

    assert Path(crestline.__file__) == installed[0]
    assert archive.name == f"crestline-{crestline.__version__}-blender-linux-x64.zip"
    return archive


@pytest.fixture(scope="module")
def crestline(extension):
    """The crestline package the add-on runs: the bundled wheel's."""
    import crestline as package

    return package


@pytest.fixture(scope="module")
def tool():
    if not TOOL.exists():
        pytest.skip(f"{TOOL} is not built (run cargo build --release)")
    return TOOL


@pytest.fixture
def scene(extension):
    """An empty scene (:func:`empty_scene`)."""
    return empty_scene()


def empty_scene():
    """The scene emptied (the extension stays enabled), at its frame 1."""
    for collection in (bpy.data.objects, bpy.data.meshes, bpy.data.curves, bpy.data.grease_pencils,
                       bpy.data.materials, bpy.data.cameras, bpy.data.lights):
        for item in list(collection):
            collection.remove(item)
    scene = bpy.context.scene
    scene.frame_set(1)
    return scene


def imported(path):
    """The mesh file imported as Blender imports OBJ files, made active."""
    bpy.ops.wm.obj_import(filepath=str(path))
    obj = bpy.context.selected_objects[0]
    bpy.context.view_layer.objects.active = obj
    return obj


def evaluated_arrays(obj):
    """The vertices and triangles of ``obj`` as evaluated, in local coordinates."""
    mesh = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh()
    mesh.calc_loop_triangles()
    vertices = np.array([v.co for v in mesh.vertices], dtype=np.float64)
    faces = np.array([t.vertices[:] for t in mesh.loop_triangles], dtype=np.int64)
    obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh_clear()
    return vertices, faces


def tools_lines(tool, folder, vertices, faces, *options):
    """``crestline ridges`` on these arrays: ``{kind: [points, ...]}``."""
    mesh = folder / "mesh.obj"
    with open(mesh, "w") as out:
        out.writelines(f"v {x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in vertices)
        out.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces)
    subprocess.run([tool, "ridges", mesh, "-o", folder / "lines.json", *options], check=True, capture_output=True)
    lines = json.loads((folder / "lines.json").read_text())["lines"]
    return {kind: [(np.array(l["points"]), l["closed"]) for l in lines if l["kind"] == kind] for kind in ("ridge", "valley")}


def lines_object(obj):
    """The one object of lines made on ``obj``."""
    children = [child for child in obj.children if "crestline_lines" in child]
    assert len(children) == 1
    return children[0]


def grease_pencil_strokes(lines, layer_name, frame=None):
    """The strokes of a layer (at ``frame``, else its only keyframe) as
    ``[(points, cyclic), ...]``."""
    layer = lines.data.layers[layer_name]
    keyframe = layer.frames[0] if frame is None else next(f for f in layer.frames if f.frame_number == frame)
    drawing = keyframe.drawing
    positions = np.empty(3 * len(drawing.attributes["position"].data), np.float32)
    drawing.attributes["position"].data.foreach_get("vector", positions)
    positions = positions.reshape(-1, 3)
    offsets = np.empty(len(drawing.curve_offsets), np.int32)
    drawing.curve_offsets.foreach_get("value", offsets)
    return [(positions[a:b], stroke.cyclic) for a, b, stroke in zip(offsets[:-1], offsets[1:], drawing.strokes)]


def curve_splines(lines, material_name):
    """The splines of the curve object with the material ``material_name``."""
    materials = [m.name for m in lines.data.materials]
    found = []
    for spline in lines.data.splines:
        if materials[spline.material_index] == material_name:
            co = np.empty(4 * len(spline.points), np.float32)
            spline.points.foreach_get("co", co)
            found.append((co.reshape(-1, 4)[:, :3], spline.use_cyclic_u))
    return found


def assert_same_lines(ours, theirs, tolerance):
    """The same number of lines, each with the same closure and points."""
    assert len(ours) == len(theirs) > 0
    for (points, closed), (expected, expected_closed) in zip(ours, theirs):
        assert bool(closed) == expected_closed
        assert points.shape == expected.shape
        assert np.abs(points - expected).max() < tolerance


def diagonal(vertices):
    return float(np.linalg.norm(vertices.max(axis=0) - vertices.min(axis=0)))


def test_grease_pencil_lines_are_the_tools_on_the_evaluated_mesh(scene, tool, tmp_path):
    bunny = imported(BUNNY)
    bunny.location = (1.0, 2.0, 3.0)
    assert bpy.ops.object.crestline_feature_lines(output="GREASE_PENCIL") == {"FINISHED"}
    lines = lines_object(bunny)
    assert lines.type == "GREASEPENCIL" and lines.parent == bunny
    assert np.allclose(np.array(lines.matrix_world), np.array(bunny.matrix_world))
    assert [layer.name for layer in lines.data.layers] == ["ridges", "valleys"]
    vertices, faces = evaluated_arrays(bunny)
    theirs = tools_lines(tool, tmp_path, vertices, faces)
    tolerance = 1e-4 * diagonal(vertices)
    for layer, kind in (("ridges", "ridge"), ("valleys", "valley")):
        assert_same_lines(grease_pencil_strokes(lines, layer), theirs[kind], tolerance)
    print(f"bunny: {len(theirs['ridge'])} ridges and {len(theirs['valley'])} valleys, as the tool's")
    # Drawn in the drawings' colours, read from the library.
    colours = {m.name: tuple(m.grease_pencil.color[:3]) for m in lines.data.materials}
    assert colours["crestline ridges stroke"][0] > 0.4 > colours["crestline ridges stroke"][2]
    assert colours["crestline valleys stroke"][2] > 0.3 > colours["crestline valleys stroke"][0]


def test_curve_lines_are_the_same_and_running_again_replaces_them(scene, tool, tmp_path):
    bunny = imported(BUNNY)
    options = dict(threshold=4.0, estimator="SHAPE_OPERATOR")
    assert bpy.ops.object.crestline_feature_lines(output="GREASE_PENCIL", **options) == {"FINISHED"}
    assert bpy.ops.object.crestline_feature_lines(output="CURVE", **options) == {"FINISHED"}
    lines = lines_object(bunny)  # the Grease Pencil object was replaced
    assert lines.type == "CURVE" and lines.data.bevel_depth > 0
    assert len(bpy.data.grease_pencils) == 0
    vertices, faces = evaluated_arrays(bunny)
    theirs = tools_lines(tool, tmp_path, vertices, faces, "--threshold", "4", "--estimator", "shape-operator")
    tolerance = 1e-4 * diagonal(vertices)
    for family, kind in (("ridges", "ridge"), ("valleys", "valley")):
        assert_same_lines(curve_splines(lines, f"crestline {family}"), theirs[kind], tolerance)


def test_a_subdivision_surface_modifier_changes_the_lines(scene, crestline):
    bunny = imported(SMALL_BUNNY)
    assert bpy.ops.object.crestline_feature_lines() == {"FINISHED"}
    plain = grease_pencil_strokes(lines_object(bunny), "ridges")
    bunny.modifiers.new("Subdivision", "SUBSURF").levels = 1
    assert bpy.ops.object.crestline_feature_lines() == {"FINISHED"}
    subdivided = grease_pencil_strokes(lines_object(bunny), "ridges")
    vertices, faces = evaluated_arrays(bunny)
    assert len(vertices) > 3 * len(bunny.data.vertices)
    expected = [(l.points, l.closed) for l in crestline.ridges(vertices, faces).of_kind("ridge")]
    assert_same_lines(subdivided, expected, 1e-4 * diagonal(vertices))
    assert len(plain) != len(subdivided) or any(a.shape != b.shape for (a, _), (b, _) in zip(plain, subdivided))


def test_baking_makes_a_keyframe_per_frame_of_the_deforming_mesh(scene, crestline):
    bunny = imported(SMALL_BUNNY)
    twist = bunny.modifiers.new("Twist", "SIMPLE_DEFORM")
    for frame, angle in ((1, 0.0), (2, 0.4), (3, 0.8)):
        twist.angle = angle
        twist.keyframe_insert("angle", frame=frame)
    scene.frame_set(2)
    assert bpy.ops.object.crestline_feature_lines(frame_start=1, frame_end=3) == {"FINISHED"}
    assert scene.frame_current == 2
    lines = lines_object(bunny)
    for layer in lines.data.layers:
        assert [f.frame_number for f in layer.frames] == [1, 2, 3]
    per_frame = {}
    for frame in (1, 2, 3):
        scene.frame_set(frame)
        vertices, faces = evaluated_arrays(bunny)
        expected = [(l.points, l.closed) for l in crestline.ridges(vertices, faces).of_kind("ridge")]
        per_frame[frame] = grease_pencil_strokes(lines, "ridges", frame)
        assert_same_lines(per_frame[frame], expected, 1e-4 * diagonal(vertices))
    assert per_frame[1][0][0].shape != per_frame[3][0][0].shape or not np.allclose(per_frame[1][0][0], per_frame[3][0][0])


def test_morse_lines_and_both_families(scene, crestline):
    bunny = imported(SMALL_BUNNY)
    vertices, faces = evaluated_arrays(bunny)
    tolerance = 1e-4 * diagonal(vertices)
    morse = [(l.points, l.closed) for l in crestline.morse(vertices, faces)]
    assert bpy.ops.object.crestline_feature_lines(lines="MORSE") == {"FINISHED"}
    lines = lines_object(bunny)
    assert [layer.name for layer in lines.data.layers] == ["ascending"]
    assert_same_lines(grease_pencil_strokes(lines, "ascending"), morse, tolerance)
    assert bpy.ops.object.crestline_feature_lines(lines="BOTH", keep_saddles=20) == {"FINISHED"}
    lines = lines_object(bunny)
    assert [layer.name for layer in lines.data.layers] == ["ridges", "valleys", "ascending"]
    fewer = [(l.points, l.closed) for l in crestline.morse(vertices, faces, keep_saddles=20)]
    assert len(fewer) < len(morse)
    assert_same_lines(grease_pencil_strokes(lines, "ascending"), fewer, tolerance)


def test_a_mesh_with_a_split_and_a_loose_vertex_is_traced_as_repaired(scene, crestline):
    # As Blender meshes often are: a vertex split in two (a seam) and a loose one.
    # The lines are those of the mesh with the copy welded and the loose vertex
    # dropped (coordinates in float32, as Blender keeps them).
    vertices, faces, _ = crestline.read_mesh(SMALL_BUNNY)
    vertices = vertices.astype(np.float32).astype(np.float64)
    n = len(vertices)
    first = int(np.argmax((faces == 0).any(axis=1)))
    split = faces.copy()
    split[first] = np.where(split[first] == 0, n, split[first])
    mesh = bpy.data.meshes.new("split bunny")
    mesh.from_pydata(np.vstack([vertices, vertices[:1], [[9.0, 9.0, 9.0]]]).tolist(), [], split.tolist())
    obj = bpy.data.objects.new("split bunny", mesh)
    scene.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    with pytest.raises(ValueError, match="renumber its vertices"):
        crestline.Mesh(*evaluated_arrays(obj))
    assert bpy.ops.object.crestline_feature_lines() == {"FINISHED"}
    expected = [(l.points, l.closed) for l in crestline.ridges(vertices, faces).of_kind("ridge")]
    assert_same_lines(grease_pencil_strokes(lines_object(obj), "ridges"), expected, 1e-4 * diagonal(vertices))


def test_escape_stops_the_computation_between_two_stages(scene):
    # The modal run's worker (Escape sets the job's cancel event): the library
    # stops at the end of the stage under way.
    job, tracing = extension_module("job"), extension_module("tracing")
    bunny = imported(BUNNY)
    options = tracing.Tracing(families="BOTH", estimator=None, scale=None, threshold=2.0, keep_saddles=100)
    running = job.LinesJob(bunny, options, [1])
    running.start(bpy.context, 1)
    while running.running() and not running.stage:
        time.sleep(0.001)
    first = running.stage
    running.cancel.set()
    while running.running():
        time.sleep(0.01)
    assert isinstance(running.error, tracing.Cancelled) and str(running.error) == first
    assert running.results == {}


def test_the_manifest_passes_blenders_validation(extension, crestline):
    # What `blender --command extension validate` runs: Blender's extension tool,
    # shipped in bpy, with the tags Blender knows.
    scripts = Path(bpy.utils.system_resource("SCRIPTS"))
    tool = scripts / "addons_core" / "bl_pkg" / "cli" / "blender_ext.py"
    tags = scripts / "modules" / "_bpy_internal" / "extensions" / "tags.py"
    checked = subprocess.run([sys.executable, tool, "validate", "--valid-tags", tags, extension],
                             check=False, capture_output=True, text=True)
    assert checked.returncode == 0 and "Success" in checked.stdout, checked.stdout + checked.stderr
    with zipfile.ZipFile(extension) as archive:
        manifest = tomllib.loads(archive.read("blender_manifest.toml").decode())
        assert manifest["version"] == crestline.__version__
        assert manifest["wheels"] == [f"./{name}" for name in archive.namelist() if name.endswith(".whl")]
        assert manifest["blender_version_min"] == "4.3.0"


@pytest.mark.parametrize("case", ["no faces", "empty", "not a mesh", "bake to curves"])
def test_a_bad_object_is_reported_not_raised(scene, case):
    if case == "not a mesh":
        obj = bpy.data.objects.new("Nothing", None)
    else:
        mesh = bpy.data.meshes.new(case)
        if case in ("no faces", "bake to curves"):
            mesh.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [(0, 1)], [] if case == "no faces" else [(0, 1, 2)])
        obj = bpy.data.objects.new(case, mesh)
    scene.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    options = dict(output="CURVE", frame_start=1, frame_end=3) if case == "bake to curves" else {}
    expected = {"no faces": "has no faces", "empty": "is empty", "not a mesh": "not a mesh",
                "bake to curves": "choose the Grease Pencil output"}[case]
    with pytest.raises(RuntimeError) as reported:
        bpy.ops.object.crestline_feature_lines(**options)
    message = str(reported.value)
    assert message.startswith("Error: Feature lines:") and expected in message and "Traceback" not in message
    assert not obj.children


def camera_scene(scene, kind, size=(400, 300)):
    """The turned bunny seen by a camera of ``kind`` (``'PERSP'`` or ``'ORTHO'``,
    with a lens shift) aimed at it from above and aside, at ``size`` pixels."""
    from mathutils import Vector

    bunny = imported(BUNNY)
    bunny.rotation_euler.z += 0.5  # upright as imported (y up in the file), turned
    bpy.context.view_layer.update()
    corners = [bunny.matrix_world @ Vector(corner) for corner in bunny.bound_box]
    center = sum(corners, Vector()) / 8
    radius = max((corner - center).length for corner in corners)
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(camera)
    scene.camera = camera
    direction = Vector((0.3, -1.0, 0.35)).normalized()
    camera.location = center + 2.8 * radius * direction
    camera.rotation_euler = (-direction).to_track_quat("-Z", "Y").to_euler()
    camera.data.type = kind
    camera.data.lens = 40
    camera.data.ortho_scale = 2.4 * radius
    camera.data.shift_x, camera.data.shift_y = (0.06, -0.04) if kind == "ORTHO" else (-0.05, 0.03)
    scene.render.resolution_x, scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    return bunny


def path_points(group):
    """The points of every path of an SVG group, (n, 2)."""
    numbers = []
    for path in group.iter(f"{SVG}path"):
        for command in path.get("d").replace("Z", "").replace("L", " ").replace("M", " ").split():
            numbers.append(float(command))
    return np.array(numbers).reshape(-1, 2)


@pytest.mark.parametrize("kind", ["PERSP", "ORTHO"])
def test_the_svg_lies_on_the_render_of_the_camera(scene, tmp_path, kind):
    bunny = camera_scene(scene, kind)
    out = tmp_path / "bunny.svg"
    assert bpy.ops.crestline.export_svg(filepath=str(out)) == {"FINISHED"}
    svg = ET.parse(out).getroot()
    assert (svg.get("width"), svg.get("height")) == ("400", "300")
    groups = {g.get("id"): g for g in svg.iter(f"{SVG}g")}
    assert {"silhouettes", "ridges", "valleys"} <= set(groups)
    drawn = path_points(groups["silhouettes"])
    seen = np.array([world_to_camera_view(scene, scene.camera, bunny.matrix_world @ v.co)[:2] for v in bunny.data.vertices])
    projected = np.column_stack([seen[:, 0] * 400, (1 - seen[:, 1]) * 300])
    assert projected.min() > 0 and projected[:, 0].max() < 400 and projected[:, 1].max() < 300  # in the frame
    difference = np.abs(np.concatenate([drawn.min(axis=0) - projected.min(axis=0), drawn.max(axis=0) - projected.max(axis=0)]))
    print(f"{kind}: silhouettes' box {drawn.min(axis=0)}-{drawn.max(axis=0)}, vertices' {projected.min(axis=0)}-{projected.max(axis=0)}")
    assert difference.max() < 2.0


def test_the_export_on_a_page_and_without_a_camera(scene, tmp_path):
    camera_scene(scene, "PERSP")
    out = tmp_path / "page.svg"
    assert bpy.ops.crestline.export_svg(filepath=str(out), page="a4", landscape=True, plot=True) == {"FINISHED"}
    svg = ET.parse(out).getroot()
    assert (svg.get("width"), svg.get("height")) == ("297mm", "210mm")
    assert {g.get("id") for g in svg.iter(f"{SVG}g")} >= {"silhouettes", "ridges", "valleys"}
    scene.camera = None
    with pytest.raises(RuntimeError) as reported:
        bpy.ops.crestline.export_svg(filepath=str(tmp_path / "none.svg"))
    assert "the scene has no camera" in str(reported.value) and "Traceback" not in str(reported.value)
    assert not (tmp_path / "none.svg").exists()


def lit_bunny_with_curves(scene, size, samples, width):
    """The bunny with its ridges and valleys as curves ``width`` thick (a share of
    its diagonal), lit by the sun, seen by the camera; Cycles on the CPU."""
    camera_scene(scene, "PERSP", size)
    assert bpy.ops.object.crestline_feature_lines(output="CURVE", width=width) == {"FINISHED"}
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    scene.collection.objects.link(sun)
    sun.rotation_euler = (0.6, 0.3, 0.8)
    sun.data.energy = 3.0
    if scene.world is None:
        scene.world = bpy.data.worlds.new("World")
    scene.world.color = (0.6, 0.6, 0.6)
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False
    scene.view_settings.view_transform = "Standard"  # the emission's colour as it is
    scene.render.image_settings.file_format = "PNG"


def rendered(scene, path):
    """Render ``scene`` into the PNG ``path``; its pixels, (height, width, 3) sRGB
    in [0, 1], the first row the top."""
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(str(path))
    pixels = np.array(image.pixels[:], dtype=np.float32).reshape(image.size[1], image.size[0], -1)[::-1, :, :3]
    bpy.data.images.remove(image)
    return pixels


def pixels_of(pixels, colour, tolerance=0.06):
    """How many pixels have ``colour`` (sRGB) to within ``tolerance`` in every channel."""
    return int((np.abs(pixels - np.array(colour)) < tolerance).all(axis=-1).sum())


def extension_module(name):
    """A module of the installed extension."""
    return __import__(f"bl_ext.user_default.crestline.{name}", fromlist=[name])


def test_a_cycles_render_shows_the_ridges_red_and_the_valleys_blue(scene, tmp_path):
    colours = extension_module("colours").family_colours()
    red, blue = colours["ridges"], colours["valleys"]
    assert red[0] > 2 * max(red[1:]) and blue[2] > 2 * blue[0]
    lit_bunny_with_curves(scene, (200, 150), 8, width=0.01)
    pixels = rendered(scene, tmp_path / "bunny.png")
    counts = pixels_of(pixels, red), pixels_of(pixels, blue)
    print(f"Cycles, 200 x 150: {counts[0]} red and {counts[1]} blue pixels")
    assert counts[0] > 80 and counts[1] > 80
    # Without the lines, neither colour is seen.
    next(obj for obj in bpy.data.objects if "crestline_lines" in obj).hide_render = True
    bare = rendered(scene, tmp_path / "bare.png")
    assert pixels_of(bare, red) + pixels_of(bare, blue) < 5


if __name__ == "__main__":
    # The documentation's picture: python test_blender.py docs/drawings/blender_bunny.png
    picture = Path(sys.argv[1]).resolve()
    installed_extension()
    the_scene = empty_scene()
    lit_bunny_with_curves(the_scene, (800, 600), 64, width=0.004)
    rendered(the_scene, picture)
