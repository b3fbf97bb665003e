"""Shared fixtures: the invmap command, sample geometries and query points.

Run by ctest (which sets PYTHONPATH and INVMAP_CLI), or by hand:
    PYTHONPATH=build/release/python /usr/bin/python3 -m pytest python/tests
"""

import os
import pathlib
import subprocess

import numpy as np
import pytest

import invmap

REPO = pathlib.Path(__file__).resolve().parents[2]
WAVY_SURFACE = REPO / "examples" / "data" / "wavy_surface.json"


def _find_cli():
    """The invmap command: $INVMAP_CLI, else <build>/cli/invmap beside the
    imported package (<build>/python/invmap)."""
    if os.environ.get("INVMAP_CLI"):
        return pathlib.Path(os.environ["INVMAP_CLI"])
    return pathlib.Path(invmap.__file__).resolve().parents[2] / "cli" / "invmap"


@pytest.fixture(scope="session")
def cli():
    """Runs the invmap command; returns the CompletedProcess (text output)."""
    path = _find_cli()
    if not path.is_file():
        pytest.skip(f"the invmap command is not built ({path}); set INVMAP_CLI")

    def run(*args, check=True):
        done = subprocess.run([str(path), *map(str, args)], capture_output=True, text=True, timeout=120)
        if check and done.returncode != 0:
            raise AssertionError(f"invmap {' '.join(map(str, args))} failed ({done.returncode}): {done.stderr}")
        return done

    return run


@pytest.fixture(scope="session")
def geometry_files(cli, tmp_path_factory):
    """Sample geometry files of every patch kind, by name: surface (B-spline
    surface, 3-D), curve (rational B-spline curve, 2-D), torus (rational
    surface), tets (quadratic tets from gmsh, i.e. Bezier cells), trimesh
    (triangle mesh, .ply) and mesh2d (a linear quad mesh in JSON, 2-D)."""
    folder = tmp_path_factory.mktemp("geometries")
    files = {"surface": WAVY_SURFACE}
    for name, what, extra in [("curve", "curve.json", []), ("torus", "torus.json", ["--spans", "4"]),
                              ("tets", "tets.msh", ["--resolution", "2"]),
                              ("trimesh", "trimesh.ply", ["--triangles", "200"])]:
        files[name] = folder / what
        cli("generate", name, "-o", files[name], *extra)
    files["mesh2d"] = folder / "mesh2d.json"
    files["mesh2d"].write_text(MESH2D_JSON)
    return files


# Two quads, one of them skewed, sharing an edge; coordinates exact in float32.
MESH2D_JSON = """{
  "format": "invmap-geometry", "version": 1, "dimension": 2,
  "patches": [{"kind": "mesh", "cell": "quad",
               "vertices": [[0, 0], [1, 0], [1, 1], [0, 1], [2.5, 0.25], [2, 1.5]],
               "cells": [[0, 1, 2, 3], [1, 4, 5, 2]]}]
}"""


def query_points(manifold, count, seed=7, spread=0.3):
    """`count` points in the manifold's bounding box grown by `spread` of its
    size, with a NaN point and an infinite one at the start."""
    info = manifold.info()
    lo, hi = np.array(info["bounds_lo"]), np.array(info["bounds_hi"])
    margin = spread * (hi - lo).max()
    rng = np.random.default_rng(seed)
    points = rng.uniform(lo - margin, hi + margin, size=(count, info["dimension"]))
    points[0, 0] = np.nan
    points[1, -1] = np.inf
    return points


def assert_results_equal(actual, expected):
    """Bit-for-bit equality of two invert() results (NaN equal to NaN)."""
    assert actual.keys() == expected.keys()
    for key in expected:
        assert actual[key].dtype == expected[key].dtype, key
        np.testing.assert_array_equal(actual[key], expected[key], err_msg=key)
