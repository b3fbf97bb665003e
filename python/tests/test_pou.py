"""invmap.manifold and Manifold.chart_points: the partition-of-unity surface
of a closed triangle mesh (docs/manifold.md). Checked against independent
references: central differences for the derivatives, dense sampling of every
chart for inversion, the command's own file for parity, and the mesh's known
defects for the error messages."""

import math
import pickle

import numpy as np
import pytest

import invmap
from conftest import assert_results_equal


def icosphere(levels):
    """The unit icosahedron split `levels` times, vertices on the unit sphere
    (valences 5 and 6), outward-oriented triangles."""
    t = (1 + 5 ** 0.5) / 2
    vertices = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
                (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    triangles = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
                 (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
                 (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    vertices = [np.array(v, float) / np.linalg.norm(v) for v in vertices]
    for _ in range(levels):
        middle = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                m = vertices[a] + vertices[b]
                vertices.append(m / np.linalg.norm(m))
                middle[key] = len(vertices) - 1
            return middle[key]

        split = []
        for a, b, c in triangles:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            split += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        triangles = split
    return np.array(vertices), np.array(triangles, dtype=np.int64)


def octahedron():
    vertices = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
    triangles = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    return vertices, triangles


def valences(triangles, count):
    return np.bincount(np.asarray(triangles).ravel(), minlength=count)


def chart_samples(manifold, valence, per_side):
    """Points of every chart on a per_side x per_side grid of its p-domain's
    disk (radius cos(pi / valence)), kept where they evaluate."""
    cells, uv = [], []
    s = np.linspace(-1, 1, per_side)
    grid = np.stack(np.meshgrid(s, s), axis=-1).reshape(-1, 2)
    grid = grid[np.hypot(grid[:, 0], grid[:, 1]) < 0.999]
    for chart, n in enumerate(valence):
        cells.append(np.full(len(grid), chart))
        uv.append(grid * math.cos(math.pi / n))
    points = manifold.chart_points(np.concatenate(cells), np.concatenate(uv))
    return points[np.isfinite(points[:, 0])]


@pytest.mark.parametrize("base", ["flat", "pn", "loop"])
def test_derivatives_match_central_differences(base):
    vertices, triangles = icosphere(1)
    manifold = invmap.manifold(vertices, triangles, base=base)
    rng = np.random.default_rng(3)
    charts = rng.integers(0, len(vertices), 40)
    radius = np.cos(np.pi / valences(triangles, len(vertices))[charts])
    angle, r = rng.uniform(0, 2 * np.pi, 40), rng.uniform(0, 0.8, 40) * radius
    uv = np.stack([r * np.cos(angle), r * np.sin(angle)], axis=1)
    jet = manifold.chart_points(charts, uv, derivatives=True)
    assert set(jet) == {"point", "du", "dv", "duu", "duv", "dvv"}
    assert np.array_equal(jet["point"], manifold.chart_points(charts, uv))
    h = 1e-5
    du, dv = np.array([h, 0.0]), np.array([0.0, h])

    def at(offset):
        return manifold.chart_points(charts, uv + offset)

    scale = 1.0  # the unit sphere's size
    np.testing.assert_allclose(jet["du"], (at(du) - at(-du)) / (2 * h), atol=1e-6 * scale)
    np.testing.assert_allclose(jet["dv"], (at(dv) - at(-dv)) / (2 * h), atol=1e-6 * scale)
    h = 1e-4
    du, dv = np.array([h, 0.0]), np.array([0.0, h])
    centre = jet["point"]
    np.testing.assert_allclose(jet["duu"], (at(du) - 2 * centre + at(-du)) / h**2, atol=1e-4)
    np.testing.assert_allclose(jet["dvv"], (at(dv) - 2 * centre + at(-dv)) / h**2, atol=1e-4)
    np.testing.assert_allclose(jet["duv"], (at(du + dv) - at(du - dv) - at(dv - du) + at(-du - dv)) / (4 * h * h),
                               atol=1e-4)


def test_inversion_never_farther_than_dense_sampling():
    vertices, triangles = icosphere(1)
    manifold = invmap.manifold(vertices, triangles, base="loop")
    samples = chart_samples(manifold, valences(triangles, len(vertices)), 61)
    rng = np.random.default_rng(11)
    directions = rng.normal(size=(24, 3))
    directions /= np.linalg.norm(directions, axis=1)[:, None]
    radii = np.repeat([0.0, 0.5, 0.95, 1.05, 1.5, 3.0], 4)
    queries = directions * radii[:, None]
    result = manifold.invert(queries)
    assert (result["status"] == 0).all()
    brute = np.array([np.min(np.linalg.norm(samples - q, axis=1)) for q in queries])
    # Never farther than any sample; no farther below them than the samples'
    # spacing (about R / 30 in chart units, times the charts' stretch).
    assert (result["distance"] <= brute + 1e-9).all()
    assert (result["distance"] >= brute - 0.01).all()
    # The reported chart and coordinates evaluate to the reported point.
    again = manifold.chart_points(result["cell"], result["params"][:, :2])
    np.testing.assert_allclose(again, result["closest"], atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(result["closest"] - queries, axis=1), result["distance"], atol=1e-12)
    # The centre is the one point every direction shares: its answer is the
    # nearest of the samples within their spacing, and it is not on the surface.
    assert result["distance"][0] > 0.5


def bipyramid(n):
    """Two apexes of valence n over an equator of n vertices (valence 4)."""
    angles = 2 * np.pi * np.arange(n) / n
    vertices = np.vstack([np.stack([np.cos(angles), np.sin(angles), 0.1 * np.cos(3 * angles)], 1),
                          [[0, 0, 1.1], [0, 0, -0.9]]])
    triangles = [(i, (i + 1) % n, n) for i in range(n)] + [((i + 1) % n, i, n + 1) for i in range(n)]
    return vertices, np.array(triangles, dtype=np.int64)


@pytest.mark.parametrize("degree", [None, 1, 2])
def test_high_valence_and_low_degree_never_farther_than_dense_sampling(degree):
    # Apexes of valence 24 (a cylinder's fan caps have such vertices), with
    # the charts' own degrees and with bilinear and biquadratic charts; points
    # up to about half the surface's size from it (far points over the flat
    # apexes can exhaust the search's budget: docs/manifold.md).
    vertices, triangles = bipyramid(24)
    manifold = invmap.manifold(vertices, triangles, base="loop", degree=degree)
    samples = chart_samples(manifold, valences(triangles, len(vertices)), 41)
    rng = np.random.default_rng(2)
    queries = samples[rng.choice(len(samples), 200)] + rng.normal(size=(200, 3)) * 0.3
    result = manifold.invert(queries)
    assert (result["status"] == 0).all()
    brute = np.array([np.min(np.linalg.norm(samples - q, axis=1)) for q in queries])
    assert (result["distance"] <= brute + 1e-9).all()
    # Points of the charts are on the surface.
    on = manifold.invert(samples[::7])
    assert (on["distance"] <= 1e-9).all()
    again = manifold.chart_points(result["cell"], result["params"][:, :2])
    np.testing.assert_allclose(again, result["closest"], atol=1e-12)


def test_the_command_writes_the_same_surface(cli, tmp_path):
    vertices, triangles = icosphere(1)
    mesh = tmp_path / "sphere.obj"
    with open(mesh, "w") as obj:
        for v in vertices:
            obj.write("v %.17g %.17g %.17g\n" % tuple(v))
        for t in triangles + 1:
            obj.write("f %d %d %d\n" % tuple(t))
    out = tmp_path / "sphere.json"
    cli("manifold", "--mesh", mesh, "--base", "pn", "--output", out)
    from_file = invmap.load(out)
    from_arrays = invmap.manifold(vertices, triangles, base="pn")
    assert from_file.info() == from_arrays.info()
    points = np.random.default_rng(5).normal(size=(200, 3))
    assert_results_equal(from_file.invert(points), from_arrays.invert(points))
    charts = np.arange(len(vertices))
    uv = np.full((len(vertices), 2), 0.2)
    np.testing.assert_array_equal(from_file.chart_points(charts, uv), from_arrays.chart_points(charts, uv))


def test_pickle_keeps_the_charts():
    vertices, triangles = octahedron()
    manifold = invmap.manifold(vertices, triangles, base="loop", degree=4)
    again = pickle.loads(pickle.dumps(manifold))
    charts, uv = np.array([0, 3, 5]), np.array([[0.1, 0.2], [0.0, 0.0], [-0.3, 0.1]])
    np.testing.assert_array_equal(again.chart_points(charts, uv), manifold.chart_points(charts, uv))
    points = np.random.default_rng(2).normal(size=(50, 3))
    assert_results_equal(again.invert(points), manifold.invert(points))


def test_points_outside_a_p_domain_are_nan():
    vertices, triangles = octahedron()
    manifold = invmap.manifold(vertices, triangles)
    radius = math.cos(math.pi / 4)
    points = manifold.chart_points(np.array([0, 0, 5]), np.array([[0, 0], [radius, 0], [0, -1.5 * radius]]))
    assert np.isfinite(points[0]).all()
    assert np.isnan(points[1:]).all()


@pytest.mark.parametrize("chart", [6, -1])
def test_a_chart_that_does_not_exist_is_named(chart):
    vertices, triangles = octahedron()
    manifold = invmap.manifold(vertices, triangles)
    with pytest.raises(invmap.InputError,
                       match=rf"^cells\[1\]: chart {chart} does not exist \(the patch has charts 0 to 5\)"):
        manifold.chart_points(np.array([0, chart]), np.zeros((2, 2)))


def test_degree_and_base_are_checked():
    vertices, triangles = octahedron()
    with pytest.raises(invmap.InputError, match="base: 'cubic', expected flat, pn or loop"):
        invmap.manifold(vertices, triangles, base="cubic")
    with pytest.raises(invmap.InputError, match="degree: 9, expected 1 to 8"):
        invmap.manifold(vertices, triangles, degree=9)
    with pytest.raises(invmap.InputError, match="triangles: expected an array of integer vertex indices"):
        invmap.manifold(vertices, triangles.astype(float))
    with pytest.raises(invmap.InputError, match=r"vertices: shape \(6, 2\), expected \(V, 3\)"):
        invmap.manifold(vertices[:, :2], triangles)
    surface = invmap.from_mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    with pytest.raises(invmap.InputError, match="patch 0: not a pou_manifold patch"):
        surface.chart_points([0], [[0, 0]])


def bad_meshes():
    vertices, triangles = octahedron()
    flipped = triangles.copy()
    flipped[0] = flipped[0][::-1]
    doubled = np.vstack([triangles, [[0, 2, 1], [2, 0, 1]]])
    with_isolated = np.vstack([vertices, [[5, 5, 5]]])
    flat = vertices.copy()
    flat[4] = 0.5 * (flat[0] + flat[2])
    unknown, infinite = vertices.copy(), vertices.copy()
    unknown[3, 1] = np.nan
    infinite[5, 2] = -np.inf
    return [
        ("boundary", vertices, triangles[:-1], r"edge \(0, 3\) is on the boundary"),
        ("orientation", vertices, flipped, r"run along edge \(\d, \d\) in the same direction"),
        ("non-manifold edge", vertices, doubled, r"edge \(0, 2\) is non-manifold"),
        ("isolated", with_isolated, triangles, r"vertex 6 belongs to no triangle"),
        ("degenerate", flat, triangles, r"triangle 0 \(vertices 0, 2, 4\) has zero area"),
        ("nan vertex", unknown, triangles, r"^manifold: vertex 3: coordinate 1 is not finite \(nan\)$"),
        ("infinite vertex", infinite, triangles, r"^manifold: vertex 5: coordinate 2 is not finite \(-inf\)$"),
        ("out of range", vertices, np.where(triangles == 5, 9, triangles), r"vertex 9|9"),
    ]


@pytest.mark.parametrize("name,vertices,triangles,message", bad_meshes(), ids=[b[0] for b in bad_meshes()])
def test_bad_meshes_name_the_vertex_or_edge(name, vertices, triangles, message):
    with pytest.raises(invmap.InputError, match=message):
        invmap.manifold(vertices, triangles)


def test_an_unsigned_index_beyond_int64_is_named_as_given():
    vertices, triangles = octahedron()
    huge = triangles.astype(np.uint64)
    huge[2, 1] = 2**64 - 1
    with pytest.raises(invmap.InputError,
                       match=r"^manifold: triangles\[2\]: vertex index 18446744073709551615 out of range \[0, 6\)"):
        invmap.manifold(vertices, huge)
