"""The package restates no default and no name list: what it documents and
applies is what the library exports, and an option left at None is the
library's default."""

import inspect
import json
import typing

import numpy as np
import pytest

import crestline
from crestline import _crestline
from crestline._jobs import DEFAULTS, NAMES, describe

# Each function and the job whose options its keyword arguments are, with the
# unit of that job's relative lengths in the documentation.
FUNCTIONS = [
    (crestline.isosurface, "iso", "voxel", {"sigma", "close"}),
    (crestline.crest_lines, "crest_lines", "voxel", {"sigma", "min_length", "min_strength", "seeds", "rng_seed"}),
    (crestline.crease_surface, "crease", "voxel", {"valley", "sigma", "strength", "min_component"}),
    (crestline.ridges, "ridges", "mean edge length",
     {"estimator", "smooth_steps", "smooth_time", "threshold", "kind", "presmooth", "solver", "fair", "all_extrema"}),
    (crestline.landmarks, "landmarks", "unit", {"radius", "persistence"}),
    (crestline.curvature, "curvature", "mean edge length", {"estimator"}),
    (crestline.morse, "morse", "mean edge length",
     {"indicator", "estimator", "keep_saddles", "criterion", "cancel", "cells", "keep_forced", "smooth"}),
    (crestline.register, "register", "unit", {"min_overlap", "max_iterations"}),
    (crestline.transfer, "transfer", "mm",
     {"scales", "iterations", "max_distance", "max_angle", "max_points", "confidence_radius", "mesh_threshold",
      "min_coverage"}),
]
# The library's options a function leaves at their defaults on purpose: the
# isosurface returns the surface alone (its curvature is crestline.curvature's),
# curvature's quality is a property of the tool's PLY file, which the package does
# not write, and registration's inner schedule (of transfer's rigid stage too) is
# the library's to tune.
NOT_ARGUMENTS = {
    "iso": {"curvature", "estimator"},
    "curvature": {"quality"},
    "register": {"coarse_iterations", "coarse_points", "tolerance"},
    "transfer": {"registration"},
}


def test_the_defaults_are_the_librarys():
    assert DEFAULTS == json.loads(_crestline.defaults())
    assert crestline.defaults() == DEFAULTS
    # A copy: changing it changes nothing.
    crestline.defaults()["iso"]["sigma"] = 7
    assert DEFAULTS == json.loads(_crestline.defaults())
    assert NAMES["estimator"] == tuple(_crestline.names()["estimator"])
    # The type of the estimator's names lists the same ones.
    assert typing.get_args(crestline._mesh.EstimatorName) == NAMES["estimator"]


@pytest.mark.parametrize("function, job, unit, arguments", FUNCTIONS)
def test_every_option_defaults_to_none_and_is_documented_with_the_librarys_value(function, job, unit, arguments):
    parameters = inspect.signature(function).parameters
    for name in arguments:
        assert parameters[name].default is None, f"{function.__name__}({name}=...) restates a default"
        if name in DEFAULTS[job] and DEFAULTS[job][name] is not None:
            assert f"{describe(DEFAULTS[job][name], unit)}" in function.__doc__, (function.__name__, name)
    # Every option the library has for the job is an argument of the same name.
    for option in set(DEFAULTS[job]) - NOT_ARGUMENTS.get(job, set()):
        assert option in parameters, f"{function.__name__} lacks {option}"


def test_draw_takes_every_option_of_the_tool_with_the_librarys_defaults(bunny_small):
    parameters = inspect.signature(crestline.draw).parameters
    for name in ("lines", "view", "size", "silhouettes"):
        assert parameters[name].default is None
        assert describe(DEFAULTS["draw"][name], "mean edge length") in crestline.draw.__doc__
    # Passing every default explicitly draws what passing none draws.
    explicit = {name: value for name, value in DEFAULTS["draw"].items() if value is not None}
    assert crestline.draw(*bunny_small, **explicit) == crestline.draw(*bunny_small)
    with pytest.raises(TypeError, match="unexpected keyword"):
        crestline.draw(*bunny_small, colour="red")


@pytest.fixture(scope="module")
def bunny_small():
    from pathlib import Path

    vertices, faces, _ = crestline.read_mesh(Path(__file__).resolve().parents[3] / "meshes" / "bunny_small.obj")
    return vertices, faces


def test_relative_defaults_are_described_in_units():
    assert describe({"units": 1.0}, "voxel") == "1 voxel"
    assert describe({"units": 3.0}, "voxel") == "3 voxels"
    assert describe(2.5, "voxel") == "2.5"


def test_unknown_options_are_refused_by_the_library():
    with pytest.raises(crestline.ArgumentError, match="unknown option of crease 'colour'"):
        _crestline.crease_surface(np.zeros((4, 4, 4), np.float32), np.eye(4), '{"colour": 1}')


def test_version():
    assert crestline.__version__ == _crestline.__version__
    assert crestline.__version__.count(".") == 2
