"""Bad calls of the package as a careless or hostile caller makes them: each
raises one clear exception naming the argument (or the file), before or instead
of a silently wrong result."""

import os
from pathlib import Path

import numpy as np
import pytest

import crestline

ROOT = Path(__file__).resolve().parents[3]
BUNNY = ROOT / "meshes" / "bunny_small.obj"


def cube(n=10):
    data = np.zeros((n, n, n), np.float32)
    data[3:7, 3:7, 3:7] = 1.0
    return data


def test_paths_may_be_bytes_or_path_like_and_nothing_else(tmp_path):
    vertices, faces, _ = crestline.read_mesh(os.fsencode(BUNNY))
    assert len(vertices) > 100
    assert np.array_equal(crestline.read_mesh(BUNNY)[0], vertices)
    # A name that is not UTF-8 reaches the file system as the bytes given.
    odd = os.fsencode(str(tmp_path)) + b"/caf\xe9.ply"
    crestline.write_mesh(odd, vertices, faces)
    assert crestline.read_mesh(odd)[1].shape == faces.shape
    with pytest.raises(crestline.FileError, match="no such file"):
        crestline.read_volume(os.fsencode(str(tmp_path / "missing.nii.gz")))
    with pytest.raises(TypeError, match="path: expected a path"):
        crestline.read_mesh(3)


@pytest.mark.parametrize("dtype", [complex, str])
def test_arrays_of_complex_numbers_or_strings_are_refused(dtype):
    with pytest.raises(TypeError, match="volume: expected real numbers, got an array of dtype"):
        crestline.isosurface(cube().astype(dtype), 0.5)
    vertices, faces, _ = crestline.read_mesh(BUNNY)
    with pytest.raises(TypeError, match="vertices: expected real numbers"):
        crestline.ridges(vertices.astype(dtype), faces)


def test_object_arrays_of_numbers_are_numbers():
    vertices, faces = crestline.isosurface(cube().astype(object), 0.5)[:2]
    assert len(faces) > 0 and np.isfinite(vertices).all()


def test_an_index_beyond_int64_is_shown_as_given_not_wrapped():
    vertices, faces, _ = crestline.read_mesh(BUNNY)
    faces = faces.astype(np.uint64)
    faces[5, 1] = 2**64 - 1
    with pytest.raises(ValueError, match=r"faces: row 5 \(\[\d+, 18446744073709551615, \d+\]\)"):
        crestline.ridges(vertices, faces)


def test_a_nibabel_image_with_a_singular_affine_names_the_affine(tmp_path):
    nib = pytest.importorskip("nibabel")
    path = tmp_path / "flat.nii"
    nib.save(nib.Nifti1Image(cube(), np.eye(4)), path)
    header = bytearray(path.read_bytes())
    header[252:256] = np.array([0, 1], "<i2").tobytes()  # qform_code 0, sform_code 1
    header[312:328] = bytes(16)  # srow_z: the third axis collapses
    path.write_bytes(bytes(header))
    loaded = nib.load(path)
    assert abs(np.linalg.det(loaded.affine[:3, :3])) < 1e-12
    with pytest.raises(ValueError, match="affine: its 3 × 3 part is singular"):
        crestline.isosurface(loaded, 0.5)


def test_levels_outside_the_image_and_pieces_larger_than_the_surface_are_errors():
    with pytest.raises(crestline.ArgumentError, match=r"level 5 is outside the image's values \[0, 1\]"):
        crestline.crest_lines(cube(), 5.0)
    with pytest.raises(crestline.ArgumentError, match="level"):
        crestline.landmarks(cube(), level=-3.0)
    with pytest.raises(crestline.ArgumentError, match="min_component 18446744073709551615 is more than"):
        crestline.crease_surface(cube(16) * 100, min_component=2**64 - 1)
