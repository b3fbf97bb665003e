"""CAD models from Python: invmap.load("part.step") and everything on it."""

import pathlib
import pickle

import numpy as np
import pytest

import invmap

SAMPLES = pathlib.Path("/usr/share/opencascade/data")
SCREW = SAMPLES / "step" / "screw.step"


@pytest.fixture(scope="module")
def screw():
    if not SCREW.is_file():
        pytest.fail(f"{SCREW} is missing: install the Debian package occt-misc")
    return invmap.load(SCREW)


def points_around(manifold, n=2000, seed=3):
    info = manifold.info()["cad"]
    lo, hi = np.array(info["model_bounds_lo"]), np.array(info["model_bounds_hi"])
    pad = 0.2 * (hi - lo)
    return np.random.default_rng(seed).uniform(lo - pad, hi + pad, size=(n, 3))


def test_info_describes_the_model(screw):
    info = screw.info()
    assert info["patches"] == 10
    cad = info["cad"]
    assert cad["format"] == "STEP"
    assert cad["faces"] == 10 and cad["solids"] == 1 and cad["shells"] == 1
    assert cad["faces_by_surface"] == {"cone": 2, "cylinder": 1, "plane": 4, "torus": 3}
    assert cad["open_parts"] == [] and cad["approximated_faces"] == []
    assert cad["edges"] > 0 and cad["vertices"] > 0


def test_results_match_the_command_line(screw, cli, tmp_path):
    points = points_around(screw, 500)
    np.savetxt(tmp_path / "p.xyz", points, fmt="%.17g")
    cli("invert", "-q", "-g", SCREW, "-p", tmp_path / "p.xyz", "-o", tmp_path / "r.csv", "--signed")
    table = np.genfromtxt(tmp_path / "r.csv", delimiter=",", skip_header=1)
    result = screw.invert(points, signed=True)
    assert np.array_equal(result["patch"], table[:, 2].astype(np.int32))
    assert np.array_equal(result["cell"], table[:, 3].astype(np.int64))
    np.testing.assert_array_equal(result["params"][:, :2], table[:, 4:6])
    np.testing.assert_array_equal(result["closest"], table[:, 7:10])
    np.testing.assert_array_equal(result["distance"], table[:, 10])
    np.testing.assert_array_equal(result["signed_distance"], table[:, 11])


def test_signed_distances(screw):
    points = points_around(screw)
    result = screw.invert(points, signed=True)
    assert np.array_equal(np.abs(result["signed_distance"]), result["distance"])
    # Far outside the model's box every point is outside the solid.
    far = screw.invert(np.array([[-200.0, 0, 0], [0, 300, 0]]), signed=True)
    assert (far["signed_distance"] > 0).all()
    inside = screw.invert(np.array([[-18.0, -1, -14]]), signed=True)
    assert inside["signed_distance"][0] < 0


def test_trim_signed_keeps_the_inside(screw):
    points = np.array([[-18.0, -1, -14], [-40.0, 0, 0]])
    assert screw.trim(points, 0.5, signed=True).tolist() == [True, False]
    assert screw.trim(points, 0.5, keep="far", signed=True).tolist() == [False, True]


def test_pickles_to_the_same_answers(screw):
    points = points_around(screw, 300)
    again = pickle.loads(pickle.dumps(screw))
    a, b = screw.invert(points, signed=True), again.invert(points, signed=True)
    for key in a:
        np.testing.assert_array_equal(a[key], b[key])
    assert again.info()["cad"]["faces"] == 10


def test_signed_needs_closed_solids():
    face = invmap.load(SAMPLES / "occ" / "face1.brep")
    with pytest.raises(invmap.InputError, match="face 0"):
        face.invert(np.zeros((1, 3)), signed=True)
    curve = invmap.from_mesh(np.array([[0.0, 0, 0], [1, 0, 0]]), np.array([[0, 1]]), cell="line")
    with pytest.raises(invmap.InputError, match="CAD model"):
        curve.invert(np.zeros((1, 3)), signed=True)


def test_bad_cad_files(tmp_path):
    garbage = tmp_path / "garbage.brep"
    garbage.write_text("not a brep\n")
    with pytest.raises(invmap.InputError, match="garbage.brep: not an OpenCascade BREP file"):
        invmap.load(garbage)
    with pytest.raises(invmap.FileError, match="no such file"):
        invmap.load(tmp_path / "missing.step")
    with pytest.raises(invmap.InputError, match="no faces"):
        invmap.load(SAMPLES / "occ" / "edge.brep")


def test_dask_invert_signed(screw):
    da = pytest.importorskip("dask.array")
    import dask
    import invmap.dask

    points = points_around(screw, 600, seed=5)
    result = invmap.dask.invert(da.from_array(points, chunks=(200, 3)), screw, signed=True)
    signed, distance = dask.compute(result["signed_distance"], result["distance"], scheduler="synchronous")
    for start in range(0, 600, 200):  # each chunk's rows are Manifold.invert's on that chunk
        alone = screw.invert(points[start:start + 200], signed=True)
        np.testing.assert_array_equal(signed[start:start + 200], alone["signed_distance"])
        np.testing.assert_array_equal(distance[start:start + 200], alone["distance"])
    face = invmap.load(SAMPLES / "occ" / "face1.brep")
    with pytest.raises(invmap.InputError, match="face 0"):  # at the call, not in a worker
        invmap.dask.invert(points, face, signed=True)


def test_point_tracker_reports_as_invert(screw):
    # Along a path around the screw the tracker gives invert's records, own
    # (u, v) of the faces (angles) and edges' pcurves included.
    points = points_around(screw, 200, seed=8)
    tracker = invmap.PointTracker(screw)
    result = screw.invert(points)
    for i, point in enumerate(points):
        answer = tracker.update(point)
        assert answer["status"] == 0
        assert abs(answer["distance"] - result["distance"][i]) <= 1e-9
        if answer["patch"] == result["patch"][i] and answer["cell"] == result["cell"][i]:
            np.testing.assert_allclose(answer["params"][:2], result["params"][i, :2], rtol=0, atol=1e-7)


def tiny_triangle(tmp_path, name="probe.obj", size=1e-7):
    """A triangle of side `size` at the origin: a model that is one point
    to a few parts in 1e7 of the screw's size."""
    path = tmp_path / name
    path.write_text(f"v 0 0 0\nv {size} 0 0\nv 0 {size} 0\nf 1 2 3\n")
    return invmap.load(path)


def translation(t):
    return [1, 0, 0, t[0], 0, 1, 0, t[1], 0, 0, 1, t[2]]


def test_distance_to_a_cad_model_is_the_point_distance(screw, tmp_path):
    # invmap.distance between the screw and a model that is one point q
    # (a tiny triangle posed at q) is q's distance to the screw: the pair
    # search on trimmed faces against the point search, with the faces'
    # parameters reported as invert reports them.
    probe = tiny_triangle(tmp_path)
    points = points_around(screw, 40, seed=11)
    inverted = screw.invert(points)
    size = np.linalg.norm(np.subtract(screw.info()["cad"]["model_bounds_hi"], screw.info()["cad"]["model_bounds_lo"]))
    for i, q in enumerate(points):
        result = invmap.distance(screw, probe, pose_b=translation(q))
        assert result["certified"]
        assert abs(result["distance"] - inverted["distance"][i]) <= 1e-6 * size
        if result["a"]["patch"] == inverted["patch"][i] and result["a"]["cell"] == inverted["cell"][i]:
            np.testing.assert_allclose(result["a"]["params"][:2], inverted["params"][i, :2], rtol=0, atol=1e-5)


def test_distance_tracker_and_all_minima_on_cad(screw, tmp_path):
    # A tracked point moving past the screw against fresh queries, and the
    # nearest of all the minima against the nearest pair.
    probe = tiny_triangle(tmp_path, "tracked.obj")
    info = screw.info()["cad"]
    lo, hi = np.array(info["model_bounds_lo"]), np.array(info["model_bounds_hi"])
    tracker = invmap.DistanceTracker(screw, probe)
    for s in np.linspace(0.0, 1.0, 12):
        q = lo + (hi - lo) * np.array([s, 0.5, 1.1])
        tracked = tracker.update(translation(q))
        fresh = invmap.distance(screw, probe, pose_b=translation(q))
        assert tracked["certified"] and fresh["certified"]
        assert abs(tracked["distance"] - fresh["distance"]) <= 1e-9 * np.linalg.norm(hi - lo)
    q = lo + (hi - lo) * np.array([0.5, 0.5, 1.1])
    result = invmap.distance(screw, probe, pose_b=translation(q), all_minima=True,
                             max_distance=0.5 * np.linalg.norm(hi - lo))
    assert result["minima"]
    assert abs(result["minima"][0]["distance"] - result["distance"]) <= 1e-9 * np.linalg.norm(hi - lo)
    minima = screw.local_minima(q[None, :], max_distance=0.5 * np.linalg.norm(hi - lo))
    assert abs(minima["distance"][0] - result["distance"]) <= 1e-6 * np.linalg.norm(hi - lo)
