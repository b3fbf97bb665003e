"""Manifolds pickle by value (the geometry, not a file path) and unpickle to
a manifold that answers bit for bit as the original."""

import copy
import os
import pickle
import shutil
import subprocess
import sys

import numpy as np
import pytest

import invmap
from conftest import assert_results_equal, query_points
from test_api import bspline_surface_dict


@pytest.mark.parametrize("name", ["surface", "curve", "torus", "tets", "trimesh", "mesh2d"])
@pytest.mark.parametrize("protocol", range(pickle.HIGHEST_PROTOCOL + 1))
def test_round_trip_every_patch_kind(geometry_files, name, protocol):
    manifold = invmap.load(geometry_files[name])
    again = pickle.loads(pickle.dumps(manifold, protocol=protocol))
    assert isinstance(again, invmap.Manifold)
    assert again.info() == manifold.info()
    points = query_points(manifold, 1000)
    assert_results_equal(again.invert(points), manifold.invert(points))


def test_reduce_rebuilds_the_manifold(geometry_files):
    manifold = invmap.load(geometry_files["curve"])
    rebuild, args = manifold.__reduce__()
    again = rebuild(*args)
    points = query_points(manifold, 200)
    assert_results_equal(again.invert(points), manifold.invert(points))


def test_round_trip_from_arrays():
    grid, weights, knots = bspline_surface_dict()
    manifold = invmap.from_bspline(grid, knots, 2, weights=weights)
    for again in (pickle.loads(pickle.dumps(manifold)), copy.deepcopy(manifold), copy.copy(manifold)):
        points = query_points(manifold, 500)
        assert_results_equal(again.invert(points), manifold.invert(points))


def test_pickle_does_not_need_the_file(geometry_files, tmp_path):
    path = tmp_path / "moved.msh"
    shutil.copy(geometry_files["tets"], path)
    manifold = invmap.load(path)
    data = pickle.dumps(manifold)
    os.remove(path)
    assert os.fsencode(path) not in data
    points = query_points(manifold, 500)
    assert_results_equal(pickle.loads(data).invert(points), manifold.invert(points))


def test_unpickle_in_another_process(geometry_files, tmp_path):
    manifold = invmap.load(geometry_files["torus"])
    points = query_points(manifold, 800)
    (tmp_path / "manifold.pickle").write_bytes(pickle.dumps(manifold))
    np.save(tmp_path / "points.npy", points)
    script = ("import pickle, sys, numpy as np\n"
              "m = pickle.load(open(sys.argv[1], 'rb'))\n"
              "r = m.invert(np.load(sys.argv[2]))\n"
              "np.savez(sys.argv[3], **r)\n")
    subprocess.run([sys.executable, "-c", script, tmp_path / "manifold.pickle", tmp_path / "points.npy",
                    tmp_path / "result.npz"], check=True, timeout=60)
    with np.load(tmp_path / "result.npz") as saved:
        assert_results_equal(dict(saved), manifold.invert(points))


def test_corrupt_state_raises_input_error(geometry_files):
    state = invmap.load(geometry_files["surface"]).__getstate__()
    for bad, message in [(b"not a geometry", "not an invmap geometry of this version"),
                         (state[:-5], "truncated"),
                         (state + b"\0", "unexpected bytes after the last patch")]:
        blank = invmap.Manifold.__new__(invmap.Manifold)
        with pytest.raises(invmap.InputError, match=message):
            blank.__setstate__(bad)
