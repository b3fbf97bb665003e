"""The documented API: load, from_mesh, from_bspline, info, invert, trim."""

import json
import pathlib
import sys
import threading
import time

import numpy as np
import pytest

import invmap
from conftest import MESH2D_JSON, WAVY_SURFACE, assert_results_equal, query_points


@pytest.fixture(scope="module")
def surface():
    return invmap.load(WAVY_SURFACE)


def test_load_path_text_and_dict_agree(surface):
    text = WAVY_SURFACE.read_text()
    points = query_points(surface, 2000)
    expected = surface.invert(points)
    for source in (str(WAVY_SURFACE), pathlib.Path(WAVY_SURFACE), text, json.loads(text)):
        assert_results_equal(invmap.load(source).invert(points), expected)


def test_load_dict_with_numpy_arrays():
    geometry = json.loads(MESH2D_JSON)
    patch = geometry["patches"][0]
    patch["vertices"] = np.array(patch["vertices"], dtype=np.float64)
    patch["cells"] = np.array(patch["cells"], dtype=np.int64)
    manifold = invmap.load(geometry)
    assert manifold.info()["cells"] == 2


def test_info(surface):
    info = surface.info()
    assert info["dimension"] == 3 and surface.dimension == 3
    assert info["patches"] == 1
    assert info["cells"] == 576
    assert info["cells_by_shape"] == {"quad 3x3": 576}
    assert len(info["bounds_lo"]) == len(info["bounds_hi"]) == 3
    assert all(lo < hi for lo, hi in zip(info["bounds_lo"], info["bounds_hi"]))
    assert info["memory_bytes"] > 0
    assert repr(surface) == "<invmap.Manifold dimension=3 patches=1 cells=576>"


def test_invert_keys_dtypes_and_shapes(surface):
    points = query_points(surface, 500)
    result = surface.invert(points, max_distance=0.05)
    expected = {"status": (np.uint8, (500,)), "patch": (np.int32, (500,)), "cell": (np.int64, (500,)),
                "params": (np.float64, (500, 3)), "closest": (np.float64, (500, 3)),
                "distance": (np.float64, (500,))}
    assert {k: (v.dtype, v.shape) for k, v in result.items()} == expected
    status = result["status"]
    assert status[0] == 2 and status[1] == 2  # NaN and infinite coordinates
    assert (status == 0).any() and (status == 1).any()
    found = status == 0
    assert (result["distance"][found] <= 0.05).all()
    assert (result["patch"][~found] == -1).all() and (result["cell"][~found] == -1).all()
    assert np.isnan(result["distance"][~found]).all() and np.isnan(result["closest"][~found]).all()
    # A surface has two parameters, in the knot range [0, 1]; w is unused.
    assert np.isnan(result["params"][:, 2]).all()
    u, v = result["params"][found, 0], result["params"][found, 1]
    assert ((0 <= u) & (u <= 1) & (0 <= v) & (v <= 1)).all()
    gap = np.linalg.norm(result["closest"][found] - points[found], axis=1)
    np.testing.assert_allclose(gap, result["distance"][found], rtol=1e-12, atol=1e-15)


def test_points_on_the_surface_are_found_at_distance_zero(surface):
    # Closest points are on the surface: inverting them again finds themselves.
    first = surface.invert(query_points(surface, 300)[2:])
    again = surface.invert(first["closest"])
    assert (again["status"] == 0).all()
    assert again["distance"].max() < 1e-9
    np.testing.assert_allclose(again["closest"], first["closest"], atol=1e-9)


def bspline_basis(knots, degree, t):
    """Cox-de Boor: the degree-`degree` B-spline basis functions at t (the
    last span closed at its end), independent of the engine."""
    knots = np.asarray(knots, dtype=float)
    n = len(knots) - degree - 1
    last = max(i for i in range(len(knots) - 1) if knots[i] < knots[i + 1])
    values = np.array([1.0 if (knots[i] <= t < knots[i + 1]) or (i == last and t == knots[-1]) else 0.0
                       for i in range(len(knots) - 1)])
    for p in range(1, degree + 1):
        nxt = np.zeros(len(knots) - p - 1)
        for i in range(len(nxt)):
            left = knots[i + p] - knots[i]
            right = knots[i + p + 1] - knots[i + 1]
            if left > 0:
                nxt[i] += (t - knots[i]) / left * values[i]
            if right > 0:
                nxt[i] += (knots[i + p + 1] - t) / right * values[i + 1]
        values = nxt
    return values[:n]


def test_points_on_the_surface_are_found_at_gap_tolerance_zero(surface):
    # QA: 46 of 50 points lying on the wavy surface came back none at 0.
    # Points at distance <= D are found for every D >= 0: here points of the
    # surface evaluated by Cox-de Boor (a rounding off it at most).
    with open(WAVY_SURFACE) as f:
        patch = json.load(f)["patches"][0]
    (p, q), (ku, kv), (nu, nv) = patch["degrees"], patch["knots"], patch["counts"]
    grid = np.array(patch["control_points"], dtype=float).reshape(nv, nu, 3)  # u fastest: grid[j_v, i_u]
    rng = np.random.default_rng(46)
    points = np.array([np.einsum("i,j,jik->k", bspline_basis(ku, p, u), bspline_basis(kv, q, v), grid)
                       for u, v in rng.uniform(0, 1, size=(200, 2))])
    result = surface.invert(points, max_distance=0)
    assert (result["status"] == 0).all(), (result["status"] != 0).sum()
    assert result["distance"].max() < 1e-12
    assert surface.trim(points, 0).all()
    assert not surface.trim(points, 0, keep="far").any()


def test_threads_do_not_change_results(surface, capfd):
    points = query_points(surface, 3000)
    one = surface.invert(points, threads=1)
    # More threads than this machine's cores too (any count beyond int), with no library warning on stderr.
    for threads in (2, 3, 7, 64, 10**12):
        assert_results_equal(one, surface.invert(points, threads=threads))
    assert capfd.readouterr().err == ""


def test_empty_points(surface):
    result = surface.invert(np.empty((0, 3)))
    assert result["params"].shape == (0, 3) and result["status"].shape == (0,)


def test_trim_matches_status(surface):
    points = query_points(surface, 1000)
    status = surface.invert(points, max_distance=0.02)["status"]
    near = surface.trim(points, 0.02)
    far = surface.trim(points, 0.02, keep="far")
    assert near.dtype == np.bool_
    np.testing.assert_array_equal(near, status == 0)
    np.testing.assert_array_equal(far, status == 1)
    assert not near[:2].any() and not far[:2].any()  # invalid points are in neither set


def test_from_mesh_matches_json_mesh():
    patch = json.loads(MESH2D_JSON)["patches"][0]
    from_arrays = invmap.from_mesh(np.array(patch["vertices"], dtype=np.float32),
                                   np.array(patch["cells"], dtype=np.int32), cell="quad")
    loaded = invmap.load(MESH2D_JSON)
    assert from_arrays.dimension == 2
    points = query_points(loaded, 1000)
    result = from_arrays.invert(points)
    assert_results_equal(result, loaded.invert(points))
    assert result["closest"].shape == (1000, 2)
    assert np.isnan(result["params"][:, 2]).all()


def test_from_mesh_triangles_default():
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 1]], dtype=np.float64)
    manifold = invmap.from_mesh(vertices, np.array([[0, 1, 2], [1, 3, 2]]))
    result = manifold.invert(np.array([[0.2, 0.2, 0.5]]))
    assert result["status"][0] == 0 and result["cell"][0] == 0
    np.testing.assert_allclose(result["params"][0, :2], [0.2, 0.2], atol=1e-12)
    np.testing.assert_allclose(result["distance"][0], 0.5, atol=1e-12)


def test_from_mesh_any_layout():
    patch = json.loads(MESH2D_JSON)["patches"][0]
    vertices = np.array(patch["vertices"], dtype=np.float64)
    cells = np.array(patch["cells"], dtype=np.int64)
    raw = np.empty(vertices.nbytes + 1, dtype=np.uint8)
    unaligned = raw[1:].view(np.float64).reshape(vertices.shape)
    unaligned[...] = vertices
    assert not unaligned.flags.aligned
    a = invmap.from_mesh(unaligned, np.asfortranarray(cells.astype(np.uint32)), cell="quad")
    b = invmap.from_mesh(vertices, cells, cell="quad")
    assert a.__getstate__() == b.__getstate__()


def bspline_surface_dict():
    """A biquadratic NURBS surface with 4 x 3 control points, non-uniform knots."""
    counts = (4, 3)
    grid = np.zeros(counts + (3,))
    for i in range(counts[0]):
        for j in range(counts[1]):
            grid[i, j] = [i, 1.5 * j, np.sin(i + 2 * j)]
    weights = 1 + 0.25 * np.arange(12).reshape(counts) % 3
    knots = [[0, 0, 0, 0.3, 1, 1, 1], [0, 0, 0, 2, 2, 2]]
    return grid, weights, knots


def test_from_bspline_matches_json_order():
    grid, weights, knots = bspline_surface_dict()
    # docs/formats.md: control points listed u fastest.
    listed = [grid[i, j].tolist() for j in range(grid.shape[1]) for i in range(grid.shape[0])]
    listed_weights = [weights[i, j] for j in range(grid.shape[1]) for i in range(grid.shape[0])]
    geometry = {"format": "invmap-geometry", "version": 1, "dimension": 3,
                "patches": [{"kind": "bspline", "degrees": [2, 2], "counts": list(grid.shape[:2]), "knots": knots,
                             "control_points": listed, "weights": listed_weights}]}
    loaded = invmap.load(geometry)
    built = invmap.from_bspline(grid, knots, degrees=2, weights=weights)
    points = query_points(loaded, 1500)
    assert_results_equal(built.invert(points), loaded.invert(points))
    v = built.invert(points)["params"][2:, 1]
    assert np.nanmin(v) >= 0 and np.nanmax(v) <= 2  # knot values of the v direction


def test_from_bspline_curve_with_flat_knots():
    control = np.array([[0, 0], [1, 2], [3, 2], [4, 0]], dtype=np.float64)
    curve = invmap.from_bspline(control, [0, 0, 0, 0, 1, 1, 1, 1], 3)
    result = curve.invert(np.array([[0.0, 0.0], [4.0, 0.0]]))
    np.testing.assert_allclose(result["params"][:, 0], [0, 1], atol=1e-12)
    assert result["distance"].max() < 1e-12


def test_invert_releases_the_gil(surface):
    # With the interpreter's switch interval made huge, a thread holding the
    # GIL keeps it until it blocks or releases it: another thread can then
    # run during an invert call only if the call releases the GIL. The other
    # thread is woken just before each call and records when it runs; a
    # record strictly inside a call proves the release, whatever the
    # machine's speed or load (were the GIL held, no record could fall
    # there). Calls repeat, larger each time, until one shows it.
    points = query_points(surface, 2000)
    interval = sys.getswitchinterval()
    sys.setswitchinterval(1000.0)
    try:
        for _ in range(12):
            go, ran = threading.Event(), []
            other = threading.Thread(target=lambda: (go.wait(), ran.append(time.perf_counter())))
            other.start()
            start = time.perf_counter()
            go.set()
            surface.invert(points, threads=1)
            end = time.perf_counter()
            other.join()
            if start < ran[0] < end:
                return
            points = np.concatenate([points, points])
        pytest.fail("no other thread ran during any of 12 invert calls: the GIL is held")
    finally:
        sys.setswitchinterval(interval)
