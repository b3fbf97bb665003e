"""Node fields in Python: Manifold.fields, Manifold.probe (the values
`invmap probe` writes), pickling with the fields, invmap.dask.probe; on a
quadratic-tet VTU file and a gmsh file with $NodeData, both written here by
hand in their documented text layouts."""

import pickle

import dask
import dask.array as da
import numpy as np
import pytest

import invmap
import invmap.dask

# Two straight-sided quadratic tets (VTK_QUADRATIC_TETRA, type 24) sharing
# the face (1, 2, 3), with point data f = 1 + x - y + x*y and v = (x, 2y, z).
CORNERS = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]], dtype=float)
TETS = [(0, 1, 2, 3), (1, 2, 3, 4)]
EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]


def f_of(p):
    return 1 + p[..., 0] - p[..., 1] + p[..., 0] * p[..., 1]


@pytest.fixture(scope="module")
def vtu(tmp_path_factory):
    points, connectivity = [], []
    for tet in TETS:
        nodes = [CORNERS[i] for i in tet] + [(CORNERS[tet[a]] + CORNERS[tet[b]]) / 2 for a, b in EDGES]
        connectivity.append(range(len(points), len(points) + 10))
        points.extend(nodes)
    points = np.array(points)
    vectors = np.c_[points[:, 0], 2 * points[:, 1], points[:, 2]]

    def numbers(values):
        return " ".join(repr(float(x)) for x in np.ravel(values))

    text = f"""<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">
<UnstructuredGrid><Piece NumberOfPoints="{len(points)}" NumberOfCells="2">
<PointData>
<DataArray type="Float64" Name="f" format="ascii">{numbers(f_of(points))}</DataArray>
<DataArray type="Float64" Name="v" NumberOfComponents="3" format="ascii">{numbers(vectors)}</DataArray>
</PointData>
<Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">{numbers(points)}</DataArray></Points>
<Cells>
<DataArray type="Int64" Name="connectivity" format="ascii">{" ".join(str(i) for c in connectivity for i in c)}</DataArray>
<DataArray type="Int64" Name="offsets" format="ascii">10 20</DataArray>
<DataArray type="UInt8" Name="types" format="ascii">24 24</DataArray>
</Cells></Piece></UnstructuredGrid></VTKFile>
"""
    path = tmp_path_factory.mktemp("fields") / "tets.vtu"
    path.write_text(text)
    return path


def inside_points(count, seed=3):
    """Points of the two tets: barycentric combinations of their corners."""
    rng = np.random.default_rng(seed)
    weights = rng.dirichlet(np.ones(4), size=count)
    tets = rng.integers(0, 2, size=count)
    return np.einsum("nk,nkd->nd", weights, CORNERS[np.array(TETS)[tets]])


def test_probe_gives_the_fields_at_the_points(vtu):
    manifold = invmap.load(vtu)
    assert manifold.fields == {"f": 1, "v": 3}
    points = inside_points(200)
    result = manifold.probe(points)
    assert set(result) == {"status", "patch", "cell", "params", "closest", "distance", "fields"}
    assert (result["status"] == 0).all()
    np.testing.assert_allclose(result["fields"]["f"], f_of(points), rtol=0, atol=1e-13)
    np.testing.assert_allclose(result["fields"]["v"], np.c_[points[:, 0], 2 * points[:, 1], points[:, 2]], atol=1e-13)
    inverted = manifold.invert(points)
    for key in inverted:
        np.testing.assert_array_equal(result[key], inverted[key], err_msg=key)


def test_names_max_distance_and_errors(vtu):
    manifold = invmap.load(vtu)
    points = np.array([[0.1, 0.1, 0.1], [9.0, 9.0, 9.0]])
    result = manifold.probe(points, ["v"], max_distance=1.0)
    assert list(result["fields"]) == ["v"]
    assert result["fields"]["v"].shape == (2, 3)
    assert np.isnan(result["fields"]["v"][1]).all() and result["status"][1] == 1
    with pytest.raises(invmap.InputError, match="no field 'w'"):
        manifold.probe(points, ["w"])
    plain = invmap.from_mesh(CORNERS[:4], np.array([[0, 1, 2, 3]]), cell="tet")
    assert plain.fields == {}
    with pytest.raises(invmap.InputError, match="no node fields"):
        plain.probe(points)


def test_pickle_keeps_the_fields(vtu):
    manifold = invmap.load(vtu)
    copy = pickle.loads(pickle.dumps(manifold))
    assert copy.fields == manifold.fields
    points = inside_points(50, seed=9)
    a, b = manifold.probe(points), copy.probe(points)
    for name in a["fields"]:
        np.testing.assert_array_equal(a["fields"][name], b["fields"][name])


def test_gmsh_node_data(tmp_path):
    # One linear tet with a view "T" at two time steps: the last one counts.
    path = tmp_path / "tet.msh"
    path.write_text("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n"
                    "0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$EndElements\n"
                    "$NodeData\n1\n\"T\"\n1\n0\n3\n0\n1\n4\n1 9\n2 9\n3 9\n4 9\n$EndNodeData\n"
                    "$NodeData\n1\n\"T\"\n1\n1\n3\n1\n1\n4\n1 0\n2 1\n3 2\n4 3\n$EndNodeData\n")
    manifold = invmap.load(path)
    result = manifold.probe([[0.2, 0.3, 0.1]])
    np.testing.assert_allclose(result["fields"]["T"], [0.2 + 2 * 0.3 + 3 * 0.1], atol=1e-15)


def test_dask_probe_matches_in_process_chunks(vtu):
    manifold = invmap.load(vtu)
    points = inside_points(900, seed=5)
    chunk = 300
    result = invmap.dask.probe(da.from_array(points, chunks=(chunk, 3)), manifold, names=["f", "v"])
    assert result["fields"]["v"].shape == (900, 3)
    status, f, v = dask.compute(result["status"], result["fields"]["f"], result["fields"]["v"],
                                scheduler="synchronous")
    parts = [manifold.probe(points[i:i + chunk]) for i in range(0, 900, chunk)]
    np.testing.assert_array_equal(status, np.concatenate([p["status"] for p in parts]))
    np.testing.assert_array_equal(f, np.concatenate([p["fields"]["f"] for p in parts]))
    np.testing.assert_array_equal(v, np.concatenate([p["fields"]["v"] for p in parts]))
    with pytest.raises(invmap.InputError, match="no field 'x'"):
        invmap.dask.probe(points, manifold, names=["x"])


def test_cli_parity(vtu, cli, tmp_path):
    manifold = invmap.load(vtu)
    points = inside_points(100, seed=11)
    np.save(tmp_path / "p.npy", points)
    cli("probe", "-q", "-g", vtu, "-p", tmp_path / "p.npy", "-o", tmp_path / "r.npy")
    rows = np.load(tmp_path / "r.npy")
    result = manifold.probe(points)
    assert rows.shape == (100, 11 + 4)
    np.testing.assert_array_equal(rows[:, 11], result["fields"]["f"])
    np.testing.assert_array_equal(rows[:, 12:15], result["fields"]["v"])
