"""invmap.read_points: LAS and PCD files (and the other point formats) as
arrays, checked against readers written here with numpy from the formats'
layouts, and against the command's results on the same file."""

import struct

import numpy as np
import pytest

import invmap
from conftest import REPO, WAVY_SURFACE

WAVY_LAS = REPO / "examples" / "data" / "wavy_scan.las"


def las_points_with_numpy(path):
    """X, Y, Z of every record, scaled and offset, from the header fields at
    the offsets the LAS specification gives (public header block)."""
    data = path.read_bytes()
    assert data[:4] == b"LASF"
    offset_to_points, = struct.unpack_from("<I", data, 96)
    record_length, = struct.unpack_from("<H", data, 105)
    count, = struct.unpack_from("<Q", data, 247) if data[25] == 4 else struct.unpack_from("<I", data, 107)
    scale = np.array(struct.unpack_from("<3d", data, 131))
    offset = np.array(struct.unpack_from("<3d", data, 155))
    records = np.frombuffer(data, dtype=np.uint8, count=count * record_length, offset=offset_to_points)
    xyz = records.reshape(count, record_length)[:, :12].copy().view("<i4").astype(np.float64)
    return xyz * scale + offset


def test_las_points_are_the_records_scaled_and_offset():
    points = invmap.read_points(str(WAVY_LAS))
    assert points.shape == (2000, 3) and points.dtype == np.float64
    np.testing.assert_array_equal(points, las_points_with_numpy(WAVY_LAS))
    np.testing.assert_array_equal(invmap.read_points(str(WAVY_LAS), dim=2), points[:, :2])


def test_las_points_invert_as_the_command_inverts_the_file(cli, tmp_path):
    out = tmp_path / "result.npy"
    cli("invert", "-g", WAVY_SURFACE, "-p", WAVY_LAS, "-o", out, "-q")
    command = np.load(out)
    result = invmap.load(WAVY_SURFACE).invert(invmap.read_points(str(WAVY_LAS)))
    np.testing.assert_array_equal(command[:, 1], result["status"])
    np.testing.assert_array_equal(command[:, 10], result["distance"])


@pytest.mark.parametrize("with_z", [True, False])
def test_binary_pcd_points_are_its_x_y_z_fields(tmp_path, with_z):
    rng = np.random.default_rng(5)
    names = ["x", "y", "z", "intensity"] if with_z else ["intensity", "y", "x"]
    dtype = np.dtype([(name, "<f4" if name != "y" else "<f8") for name in names])
    cloud = np.zeros(300, dtype=dtype)
    for name in names:
        cloud[name] = rng.normal(size=300)
    cloud["x"][7] = np.nan
    header = ("VERSION 0.7\nFIELDS " + " ".join(names) +
              "\nSIZE " + " ".join(str(dtype[n].itemsize) for n in names) +
              "\nTYPE " + " ".join("F" for _ in names) + "\nCOUNT " + " ".join("1" for _ in names) +
              "\nWIDTH 300\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 300\nDATA binary\n")
    path = tmp_path / "cloud.pcd"
    path.write_bytes(header.encode() + cloud.tobytes())
    points = invmap.read_points(str(path))
    columns = ["x", "y", "z"] if with_z else ["x", "y"]
    expected = np.stack([cloud[c].astype(np.float64) for c in columns], axis=1)
    np.testing.assert_array_equal(points, expected)


def test_bad_and_missing_files_raise_with_the_file_named(tmp_path):
    lying = bytearray(WAVY_LAS.read_bytes())
    struct.pack_into("<Q", lying, 247, 2001)  # one point more than the file holds
    struct.pack_into("<I", lying, 107, 0)
    bad = tmp_path / "lying.las"
    bad.write_bytes(bytes(lying))
    with pytest.raises(invmap.InputError, match="lying.las: the header's 2001 point records"):
        invmap.read_points(str(bad))
    laz = tmp_path / "scan.laz"
    laz.write_bytes(WAVY_LAS.read_bytes())
    with pytest.raises(invmap.InputError, match="compressed LAZ is not supported"):
        invmap.read_points(str(laz))
    with pytest.raises(invmap.FileError, match="no such file"):
        invmap.read_points(str(tmp_path / "missing.pcd"))
    with pytest.raises(invmap.InputError, match="dim: 4"):
        invmap.read_points(str(WAVY_LAS), dim=4)
