"""A type checker accepts the package's annotations and stubs: mypy in strict mode
on a script that uses every function, and rejects a wrong call."""

import subprocess
import sys
import textwrap

import pytest

USAGE = textwrap.dedent('''
    import numpy as np
    import crestline

    vertices, faces, repairs = crestline.read_mesh("meshes/bunny.obj")
    field: crestline.Curvature = crestline.curvature(vertices, faces, estimator="jet-fit")
    k: np.ndarray = field["k_max"]
    lines: crestline.Lines = crestline.ridges(vertices, faces, threshold=3.0)
    first: crestline.Line = lines[0]
    length: float = first.length()
    cells = crestline.morse(vertices, faces, indicator=k, keep_saddles=10)
    svg: str = crestline.draw(vertices, faces, lines, view=(20.0, 15.0))
    pair: tuple[str, bytes] = crestline.draw(vertices, faces, cells, png=True)
    brain: crestline.Volume = crestline.read_volume("volumes/mni152_t1_1mm.nii.gz")
    skin, triangles = crestline.isosurface(brain, 60.0)
    crests: crestline.Lines = crestline.crest_lines(brain, 60.0, sigma=1.5, kind="crest")
    marks = crestline.landmarks(crests, radius=5.0, persistence=2.0)
    motion = crestline.register(crests, crests)["matrix"]
    sheet = crestline.crease_surface(brain.data, spacing=(1.0, 1.0, 1.0))["faces"]
    built = crestline.Mesh(vertices, faces)
    unit: float = built.mean_edge_length()
    again: crestline.Lines = crestline.ridges(built, threshold=3.0)
    fixed, fixed_faces, fixes = crestline.repair_mesh(vertices, faces)
    ridge_color: str = crestline.colors()[crestline.families()[first.kind]]
    try:
        crestline.read_mesh("missing.obj")
    except crestline.FileError as error:
        where = error.path
''')


def mypy(tmp_path, source):
    pytest.importorskip("mypy")
    script = tmp_path / "usage.py"
    script.write_text(source)
    return subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-incremental", str(script)],
                          capture_output=True, text=True)


def test_mypy_accepts_typed_use(tmp_path):
    result = mypy(tmp_path, USAGE)
    assert result.returncode == 0, result.stdout + result.stderr


def test_mypy_rejects_a_wrong_call(tmp_path):
    result = mypy(tmp_path, USAGE + 'crestline.ridges(vertices, faces, smooth_steps="many")\n')
    assert result.returncode == 1 and "smooth_steps" in result.stdout, result.stdout
    result = mypy(tmp_path, USAGE + 'crestline.crest_lines(brain, 60.0, kind="ridges")\n')
    assert result.returncode == 1 and "kind" in result.stdout, result.stdout
