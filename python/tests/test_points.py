"""Query point dtypes and memory layouts: every variant gives the same results,
and float32/float64 arrays are read in place, without a copy."""

import tracemalloc

import numpy as np
import pytest

import invmap
from conftest import WAVY_SURFACE, assert_results_equal, query_points


@pytest.fixture(scope="module")
def surface():
    return invmap.load(WAVY_SURFACE)


@pytest.fixture(scope="module")
def points(surface):
    return query_points(surface, 1500)


def unaligned(array):
    """A copy of `array` whose data starts one byte past an aligned address."""
    raw = np.empty(array.nbytes + 1, dtype=np.uint8)
    view = raw[1:].view(array.dtype).reshape(array.shape)
    view[...] = array
    assert not view.flags.aligned
    return view


def padded_columns(array, before=1, after=2):
    """`array` as a column slice of a wider C-ordered array."""
    wide = np.full((array.shape[0], before + array.shape[1] + after), -7.0, dtype=array.dtype)
    wide[:, before:before + array.shape[1]] = array
    return wide[:, before:before + array.shape[1]]


def read_only(array):
    copy = np.array(array)
    copy.flags.writeable = False
    return copy


def every_other_row(array):
    tall = np.zeros((2 * array.shape[0], array.shape[1]), dtype=array.dtype)
    tall[::2] = array
    return tall[::2]


LAYOUTS = {
    "c_order": lambda a: np.ascontiguousarray(a),
    "fortran_order": np.asfortranarray,
    "column_slice": padded_columns,
    "row_stride": every_other_row,
    "read_only": read_only,
    "unaligned": unaligned,
    "negative_stride": lambda a: a[::-1].copy()[::-1],
    "big_endian": lambda a: a.astype(a.dtype.newbyteorder(">")),
    "list": lambda a: a.tolist(),
}


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("layout", LAYOUTS)
def test_layouts_give_identical_results(surface, points, dtype, layout):
    base = points.astype(dtype)
    # The engine computes in double: float32 input means its exact float64 value.
    expected = surface.invert(base.astype(np.float64))
    assert_results_equal(surface.invert(LAYOUTS[layout](base)), expected)


def test_broadcast_rows(surface, points):
    one = surface.invert(points[5:6])
    many = surface.invert(np.broadcast_to(points[5], (40, 3)))
    for key in one:
        np.testing.assert_array_equal(many[key], np.repeat(one[key], 40, axis=0), err_msg=key)


@pytest.mark.parametrize("dtype", [np.int32, np.int64, np.uint16, np.float16])
def test_other_real_dtypes_are_converted(surface, dtype):
    integral = np.array([[0, 0, 1], [1, 1, 0], [0, 1, 0]], dtype=dtype)
    assert_results_equal(surface.invert(integral), surface.invert(integral.astype(np.float64)))


def peak_traced_bytes(function):
    """Peak Python-heap memory (numpy's allocations included) while `function` runs."""
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        base = tracemalloc.get_traced_memory()[0]
        function()
        return tracemalloc.get_traced_memory()[1] - base
    finally:
        tracemalloc.stop()


def test_float_arrays_are_not_copied():
    # Results live in C++ vectors (not traced); a copy of the points would be
    # a traced numpy allocation of at least the array's size.
    triangles = invmap.from_mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float64), np.array([[0, 1, 2]]))
    rng = np.random.default_rng(3)
    base = rng.random((40000, 3))
    for dtype in (np.float64, np.float32):
        typed = base.astype(dtype)
        for layout in ("c_order", "fortran_order", "column_slice", "row_stride"):
            array = LAYOUTS[layout](typed)
            peak = peak_traced_bytes(lambda: triangles.invert(array))
            assert peak < typed.nbytes / 4, (dtype, layout, peak)
    converted = base.astype(np.int32)
    assert peak_traced_bytes(lambda: triangles.invert(converted)) >= base.nbytes


@pytest.mark.parametrize("bad, message", [
    (np.zeros((4, 2)), r"points: shape \(4, 2\), expected \(N, 3\) for a 3-D geometry"),
    (np.zeros(3), r"points: shape \(3,\), expected \(N, 3\)"),
    (np.zeros((2, 3, 1)), r"points: shape \(2, 3, 1\)"),
    (np.zeros((4, 3), dtype=bool), r"points: dtype bool, expected float32 or float64"),
    (np.zeros((4, 3), dtype=complex), r"points: dtype complex128"),
    ([["a", "b", "c"]], r"points: dtype <U1"),
    ([[1, 2], [3]], r"points"),
])
def test_bad_points_raise_input_error(surface, bad, message):
    with pytest.raises(invmap.InputError, match=message):
        surface.invert(bad)


@pytest.mark.parametrize("kwargs, message", [
    ({"max_distance": -1.0}, r"max_distance: -1, expected a number >= 0"),
    ({"max_distance": float("nan")}, r"max_distance: nan"),
    ({"threads": -2}, r"threads: -2, expected >= 0"),
])
def test_bad_options_raise_input_error(surface, points, kwargs, message):
    with pytest.raises(invmap.InputError, match=message):
        surface.invert(points, **kwargs)
    assert issubclass(invmap.InputError, ValueError)


def test_bad_trim_keep(surface, points):
    with pytest.raises(invmap.InputError, match="keep: 'middle', expected 'near' or 'far'"):
        surface.trim(points, 0.1, keep="middle")
