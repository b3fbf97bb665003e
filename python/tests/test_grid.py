"""invmap.grid: adaptive grids for implicit complexes from Python, checked
against the reference implementation's published counts and analytic zero sets."""

import json
import os

import numpy as np
import pytest

import invmap

DATA = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "data", "implicit")
SPHERE = {"type": "sphere", "center": [0.5112321, 0.51412521, 0.51], "radius": 0.3}


def test_sphere_matches_the_reference_count_and_the_true_surface():
    result = invmap.grid(os.path.join(DATA, "1-sphere.json"), epsilon=1e-3,
                         initial_grid=os.path.join(DATA, "cube6.msh"))
    stats = result["stats"]
    # The reference implementation's published count: 30,218 tets, 14,636 active.
    assert abs(stats["cells"] - 30218) <= 30
    assert stats["active_cells"] == 14636
    assert result["cells"].shape == (stats["cells"], 4)
    assert result["vertices"].shape == (stats["vertices"], 3)
    assert result["values"].shape == (stats["vertices"], 1)
    assert result["active"].dtype == np.bool_ and result["active"].sum() == stats["active_cells"]
    # Grid values are the function at the vertices.
    centre = np.array(SPHERE["center"])
    expected = 0.3 - np.linalg.norm(result["vertices"] - centre, axis=1)
    assert np.allclose(result["values"][:, 0], expected, atol=1e-15)
    # The extracted surface lies within epsilon of the sphere.
    zs = result["zero_sets"]
    assert zs["triangles"].shape[0] > 1000
    distance = np.abs(np.linalg.norm(zs["vertices"] - centre, axis=1) - 0.3)
    assert distance.max() <= 1e-3
    assert (zs["triangle_labels"][:, 0] == 0).all() and (zs["triangle_labels"][:, 1:] == -1).all()


def test_lists_of_dicts_and_the_same_result_for_any_thread_count():
    circles = [{"type": "sphere", "center": [0.5, -1.499], "radius": 2.0},
               {"type": "sphere", "center": [0.5, 2.499], "radius": 2.0}]
    one = invmap.grid(circles, epsilon=1e-4, box=(0, 0, 1, 1), threads=1)
    two = invmap.grid(json.dumps(circles), epsilon=1e-4, box=(0, 0, 1, 1), threads=2)
    assert one["dimension"] == 2 and one["cells"].shape[1] == 3
    assert np.array_equal(one["cells"], two["cells"]) and np.array_equal(one["vertices"], two["vertices"])
    # The two nearly tangent circles cross at (0.5 +- h, 0.5).
    h = np.sqrt(4 - 1.999 ** 2)
    points = one["zero_sets"]["vertices"][one["zero_sets"]["points"]]
    for x in (0.5 - h, 0.5 + h):
        assert np.min(np.hypot(points[:, 0] - x, points[:, 1] - 0.5)) <= 1e-4


def test_csg_tree_from_a_list():
    functions = [dict(SPHERE), {"type": "plane", "point": [0.5, 0.5, 0.5], "normal": [0, 0, 1]}]
    # Inside the sphere (Negation: f >= 0) and below the plane (f <= 0).
    tree = [{"type": "Intersection", "elements": [2, -2]}, {"type": "Negation", "elements": [-1, 0]}]
    result = invmap.grid(functions, mode="csg", tree=tree, epsilon=1e-3, box=(0, 0, 0, 1, 1, 1))
    zs = result["zero_sets"]
    vertices = zs["vertices"][zs["triangles"].reshape(-1)]
    assert len(vertices) > 0
    assert (vertices[:, 2] <= 0.5 + 1e-9).all()


def test_errors_name_the_source_and_line():
    bad = [dict(SPHERE), {"type": "sphere", "center": [0, 0, 0], "radius": -1}]
    with pytest.raises(invmap.InputError, match=r"<functions>:\d+: .*radius"):
        invmap.grid(bad, box=(0, 0, 0, 1, 1, 1))
    with pytest.raises(invmap.FileError, match="missing.json"):
        invmap.grid("missing.json", box=(0, 0, 0, 1, 1, 1))
    with pytest.raises(invmap.InputError, match="exactly one of box and initial_grid"):
        invmap.grid([SPHERE])
    with pytest.raises(invmap.InputError, match="needs a tree"):
        invmap.grid([SPHERE], mode="csg", box=(0, 0, 0, 1, 1, 1))
    with pytest.raises(invmap.InputError, match="mode"):
        invmap.grid([SPHERE], mode="voronoi", box=(0, 0, 0, 1, 1, 1))
    with pytest.raises(invmap.InputError, match="for mode \"csg\" only"):
        invmap.grid([SPHERE], tree=[{"type": "Negation", "elements": [-1, 0]}], box=(0, 0, 0, 1, 1, 1))
    with pytest.raises(invmap.InputError, match="expected 3 numbers"):
        invmap.grid([{"type": "sphere", "center": [0.5, 0.5], "radius": 0.3}], box=(0, 0, 0, 1, 1, 1))
