"""Bad inputs raise InputError (a ValueError) or FileError (an OSError) with
exactly the message the invmap command prints after "invmap: "."""

import json
import os

import numpy as np
import pytest

import invmap
from conftest import MESH2D_JSON


def bspline_json(**changes):
    patch = {"kind": "bspline", "degrees": [2], "counts": [3], "knots": [[0, 0, 0, 1, 1, 1]],
             "control_points": [[0, 0, 0], [1, 1, 0], [2, 0, 0]]}
    patch.update(changes)
    return json.dumps({"format": "invmap-geometry", "version": 1, "dimension": 3, "patches": [patch]}, indent=1)


# name -> (file content or None for "do not create", expected Python exception class)
BAD_GEOMETRIES = {
    "missing.json": (None, invmap.FileError),
    "empty.json": ("", invmap.InputError),
    "syntax.json": ('{"format": "invmap-geometry",\n "version": 1,\n "dimension": 3 "patches": []}', invmap.InputError),
    "decreasing_knots.json": (bspline_json(knots=[[0, 0, 0, 1, 0.5, 1]]), invmap.InputError),
    "too_few_points.json": (bspline_json(control_points=[[0, 0, 0], [1, 1, 0]]), invmap.InputError),
    "high_degree.json": (bspline_json(degrees=[40], knots=[[0] * 41 + [1] * 41], counts=[41],
                                      control_points=[[i, 0, 0] for i in range(41)]), invmap.InputError),
    "bad_index.json": (MESH2D_JSON.replace("[1, 4, 5, 2]", "[1, 4, 9, 2]"), invmap.InputError),
    "unknown_field.json": (bspline_json(weight=[1, 1, 1]), invmap.InputError),
    "no_faces.obj": ("v 0 0 0\nv 1 0 0\n", invmap.InputError),
    "unknown.ext": ("hello\n", invmap.InputError),
}


@pytest.mark.parametrize("name", BAD_GEOMETRIES)
def test_bad_geometry_files_match_the_command_line(cli, tmp_path, name):
    content, error_class = BAD_GEOMETRIES[name]
    path = tmp_path / name
    if content is not None:
        path.write_text(content)
    done = cli("info", "--geometry", path, check=False)
    assert done.returncode == 3, done.stderr
    assert done.stderr.startswith("invmap: ")
    message = done.stderr[len("invmap: "):].rstrip("\n")
    with pytest.raises(error_class) as caught:
        invmap.load(path)
    assert str(caught.value) == message


def test_directory_is_a_file_error(tmp_path):
    with pytest.raises(invmap.FileError) as caught:
        invmap.load(tmp_path)
    assert isinstance(caught.value, OSError)
    assert str(tmp_path) in str(caught.value)


def test_json_text_errors_name_the_source_and_line():
    with pytest.raises(invmap.InputError, match=r"^<json>:\d+: patches\[0\]\.knots\[0\]: decreasing at index 4"):
        invmap.load(bspline_json(knots=[[0, 0, 0, 1, 0.5, 1]]))
    with pytest.raises(invmap.InputError, match=r"^<dict>:1: "):
        invmap.load({"format": "invmap-geometry", "version": 1, "dimension": 4, "patches": []})


def test_load_rejects_other_types():
    with pytest.raises(TypeError, match="load: expected a path, JSON text or a dict, got int"):
        invmap.load(42)


def test_manifold_has_no_public_constructor():
    with pytest.raises(TypeError):
        invmap.Manifold()


TRIANGLE = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float64)


@pytest.mark.parametrize("vertices, cells, cell, message", [
    (TRIANGLE, [[0, 1, 2]], "pyramid", r"cell: 'pyramid', expected line, tri, quad, tet, hex or wedge"),
    (TRIANGLE, [[0, 1, 2]], "quad", r"cells: shape \(1, 3\), a quad cell has 4 vertices"),
    (TRIANGLE, [[0, 1, 3]], "tri", r"^from_mesh: patch 0: cells\[0\]: vertex index 3"),
    (TRIANGLE, [[0.0, 1.0, 2.0]], "tri", r"cells: expected an array of integer vertex indices"),
    (TRIANGLE[:, :1], [[0, 1, 2]], "tri", r"vertices: shape \(3, 1\), expected \(V, 2\) or \(V, 3\)"),
    (TRIANGLE[:, :2], [[0, 1, 2]], "tet", r"cells: shape \(1, 3\), a tet cell has 4 vertices"),
    (["a", "b"], [[0, 1, 2]], "tri", r"vertices: expected an array of real numbers"),
])
def test_from_mesh_errors(vertices, cells, cell, message):
    with pytest.raises(invmap.InputError, match=message):
        invmap.from_mesh(vertices, np.asarray(cells), cell=cell)


def test_from_mesh_names_an_unsigned_index_beyond_int64_as_given():
    cells = np.array([[0, 1, 2**64 - 1]], dtype=np.uint64)
    with pytest.raises(invmap.InputError,
                       match=r"^from_mesh: patch 0: cells\[0\]: vertex index 18446744073709551615 out of range \[0, 3\)"):
        invmap.from_mesh(TRIANGLE, cells)
    with pytest.raises(invmap.InputError, match=r"vertex index 3 out of range"):
        invmap.from_mesh(TRIANGLE, np.array([[0, 1, 3]], dtype=np.uint64))


def test_from_bspline_errors():
    control = np.array([[0, 0], [1, 2], [3, 2], [4, 0]], dtype=np.float64)
    with pytest.raises(invmap.InputError, match=r"^from_bspline: patch 0: knots\[0\]: length 7, expected"):
        invmap.from_bspline(control, [0, 0, 0, 0, 1, 1, 1], 3)
    with pytest.raises(invmap.InputError, match=r"weights: shape \(3,\), expected \(4,\)"):
        invmap.from_bspline(control, [0, 0, 0, 0, 1, 1, 1, 1], 3, weights=[1, 1, 1])
    with pytest.raises(invmap.InputError, match=r"^from_bspline: patch 0: weights"):
        invmap.from_bspline(control, [0, 0, 0, 0, 1, 1, 1, 1], 3, weights=[1, -1, 1, 1])
    with pytest.raises(invmap.InputError, match=r"control_points: shape \(4,\)"):
        invmap.from_bspline(control[:, 0], [0, 0, 0, 0, 1, 1, 1, 1], 3)


def test_file_error_is_picklable(tmp_path):
    # Errors raised in Dask workers travel back to the client by pickle.
    import pickle
    with pytest.raises(invmap.FileError) as caught:
        invmap.load(tmp_path / "absent.json")
    again = pickle.loads(pickle.dumps(caught.value))
    assert type(again) is invmap.FileError and str(again) == str(caught.value)
    assert os.fspath(tmp_path / "absent.json") in str(again)
