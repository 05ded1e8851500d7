"""Meshes: arrays in and out bit for bit, every reader and writer, info, check,
welding, pickling, and every refusal as a MeshError with the library's message."""

import gzip
import pickle

import numpy as np
import pytest

import multires
from multires import MeshError


def test_arrays_round_trip_bit_for_bit(sphere):
    v, f = sphere.vertices, sphere.faces
    assert v.dtype == np.float64 and v.shape == (sphere.n_vertices, 3)
    assert f.dtype == np.int64 and f.shape == (sphere.n_faces, 3)
    back = multires.Mesh.from_arrays(v, f)
    assert back.vertices.tobytes() == v.tobytes()
    assert np.array_equal(back.faces, f)


def test_awkward_float_values_survive():
    v = np.array([[0.1, 1e-310, -0.0], [np.nextafter(1.0, 2.0), 1e300, 3.0],
                  [np.pi, -np.e, 2.0 ** -1074]])
    m = multires.Mesh.from_arrays(v, np.array([[0, 1, 2]]))
    assert m.vertices.tobytes() == v.tobytes()


@pytest.mark.parametrize("dtype", [np.int8, np.uint8, np.int16, np.uint16, np.int32,
                                   np.uint32, np.int64, np.uint64])
def test_any_integer_dtype_for_faces(dtype, sphere):
    f = sphere.faces
    if np.iinfo(dtype).max < f.max():
        f = f[f.max(axis=1) < np.iinfo(dtype).max]
    m = multires.Mesh.from_arrays(sphere.vertices, f.astype(dtype))
    assert np.array_equal(m.faces, f)


def test_non_contiguous_and_float32_inputs(sphere):
    v = np.asfortranarray(sphere.vertices)
    f = sphere.faces[:, :][::1]
    m = multires.Mesh.from_arrays(v, np.asfortranarray(f))
    assert np.array_equal(m.vertices, sphere.vertices)
    m32 = multires.Mesh.from_arrays(sphere.vertices.astype(np.float32), f)
    assert np.array_equal(m32.vertices, sphere.vertices.astype(np.float32).astype(np.float64))


def test_mesh_error_is_a_value_error():
    assert issubclass(MeshError, ValueError)
    assert issubclass(multires.EditError, MeshError)
    assert issubclass(multires.RecipeError, MeshError)


@pytest.mark.parametrize("vertices,faces,message", [
    (np.zeros((3, 3), dtype=np.int64), [[0, 1, 2]], "float"),
    (np.zeros((3, 2)), [[0, 1, 2]], "shape"),
    (np.zeros(9), [[0, 1, 2]], "shape"),
    (np.array([[0, 0, 0], [1, 0, 0], [0, np.nan, 0]]), [[0, 1, 2]], "row 2"),
    (np.array([[0, 0, 0], [1, 0, 0], [0, np.inf, 0]]), [[0, 1, 2]], "non-finite"),
    (np.eye(3), np.array([[0.0, 1.0, 2.0]]), "integer"),
    (np.eye(3), np.array([[0, 1]]), "shape"),
    (np.eye(3), np.array([[0, 1, 3]]), "out of range for 3 vertices"),
    (np.eye(3), np.array([[0, 1, -1]]), "out of range"),
    (np.zeros((0, 3)), np.zeros((0, 3), dtype=int), "no|empty|vertices"),
    (np.eye(3), np.array([["a", "b", "c"]]), "integer"),
])
def test_bad_arrays_raise_mesh_error(vertices, faces, message):
    with pytest.raises(MeshError, match=message):
        multires.Mesh.from_arrays(vertices, faces)


def test_setting_vertices_checks_shape_and_values(sphere):
    with pytest.raises(MeshError, match="shape"):
        sphere.vertices = np.zeros((3, 3))
    bad = sphere.vertices
    bad[5, 1] = np.nan
    with pytest.raises(MeshError, match="row 5"):
        sphere.vertices = bad
    moved = sphere.vertices + 1.0
    sphere.vertices = moved
    assert sphere.vertices.tobytes() == moved.tobytes()


@pytest.mark.parametrize("ext", ["obj", "ply", "off", "stl", "obj.gz", "ply.gz", "off.gz"])
def test_write_read_every_format(tmp_path, torus, ext):
    path = tmp_path / f"torus.{ext}"
    torus.write(path)
    back = multires.read(path, weld="off")
    assert (back.n_vertices, back.n_faces) == (torus.n_vertices, torus.n_faces)
    if ext == "stl":
        # STL has no shared vertices: its reader welds them, in its own order
        # (same faces, same corners, float32 positions)
        assert np.allclose(back.vertices[back.faces], torus.vertices[torus.faces], atol=1e-6)
        return
    assert np.array_equal(back.faces, torus.faces)
    if ext in ("ply", "ply.gz"):
        # binary PLY keeps every bit
        assert back.vertices.tobytes() == torus.vertices.tobytes()
    else:
        assert np.allclose(back.vertices, torus.vertices, atol=1e-6)


def test_stl_is_welded_by_its_reader(tmp_path, torus):
    torus.write(tmp_path / "t.stl")
    back = multires.read(tmp_path / "t.stl")
    assert back.info()["genus"] == 1
    assert back.n_faces == torus.n_faces


def test_missing_file_and_bad_formats(tmp_path):
    with pytest.raises(FileNotFoundError, match="nope.obj"):
        multires.read(tmp_path / "nope.obj")
    (tmp_path / "x.xyz").write_text("1 2 3\n")
    with pytest.raises(MeshError, match="x.xyz"):
        multires.read(tmp_path / "x.xyz")
    (tmp_path / "bad.off").write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n")
    with pytest.raises(MeshError, match="bad.off"):
        multires.read(tmp_path / "bad.off")
    (tmp_path / "bad.ply").write_bytes(b"ply\nformat binary_little_endian 1.0\nelement vertex 99\n")
    with pytest.raises(MeshError):
        multires.read(tmp_path / "bad.ply")
    (tmp_path / "bad.obj.gz").write_bytes(b"not gzip at all")
    with pytest.raises(MeshError):
        multires.read(tmp_path / "bad.obj.gz")
    with pytest.raises(MeshError, match="weld"):
        multires.read(tmp_path / "bad.off", weld="sometimes")
    with pytest.raises(MeshError, match="weld"):
        multires.read(tmp_path / "bad.off", weld=-1.0)


def test_write_to_unknown_extension_refused(tmp_path, sphere):
    with pytest.raises(MeshError):
        sphere.write(tmp_path / "s.xyz")


def test_info_counts(sphere, torus, grid):
    i = sphere.info()
    assert (i["vertices"], i["faces"], i["edges"]) == (2562, 5120, 7680)
    assert (i["genus"], i["components"], i["boundary_loops"], i["euler"]) == (0, 1, 0, 2)
    t = torus.info()
    assert (t["genus"], t["boundary_loops"], t["euler"]) == (1, 0, 0)
    g = grid.info()
    assert (g["boundary_loops"], g["components"], g["genus"]) == (1, 1, 0)
    assert g["vertices"] == 21 * 15 and g["faces"] == 2 * 20 * 14
    assert g["boundary_vertices"] == 2 * (21 + 15) - 4
    assert np.allclose(g["bbox_max"], [2.0, 1.4, 0.0]) and g["diagonal"] > 0
    assert set(sphere.info()) >= {"vertices", "faces", "edges", "boundary_loops",
                                  "components", "genus", "euler", "non_manifold_vertices",
                                  "bbox_min", "bbox_max", "diagonal"}


def test_reader_fixes_and_welding():
    # a triangle soup of a tetrahedron: 12 vertices, 4 faces
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    tris = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
    soup_v = p[tris.ravel()]
    soup_f = np.arange(12).reshape(4, 3)
    soup = multires.Mesh.from_arrays(soup_v, soup_f)
    assert soup.info()["boundary_loops"] == 4
    welded = soup.welded()
    assert welded.n_vertices == 4 and welded.info()["boundary_loops"] == 0
    assert welded.info()["fixes"]["welded_vertices"] == 8
    assert soup.welded("off").n_vertices == 12
    assert soup.welded(1e-9).n_vertices == 4
    # a repeated index drops the face; the report says so
    m = multires.Mesh.from_arrays(p, np.array([[0, 1, 2], [0, 0, 3]]))
    assert m.n_faces == 1 and m.info()["fixes"]["dropped_faces"] + m.info()["fixes"]["dropped_triangles"] >= 1


def test_check_passes(sphere, torus, grid):
    for m in (sphere, torus, grid):
        m.check()


def test_pickle_and_copy(sphere):
    back = pickle.loads(pickle.dumps(sphere))
    assert back.vertices.tobytes() == sphere.vertices.tobytes()
    assert np.array_equal(back.faces, sphere.faces)
    c = sphere.copy()
    c.vertices = c.vertices * 2
    assert not np.array_equal(c.vertices, sphere.vertices)


def test_generators_refuse_bad_sizes():
    with pytest.raises(MeshError):
        multires.torus(1.0, 2.0, 10, 10)
    with pytest.raises(MeshError):
        multires.grid(0, 3)
    with pytest.raises(MeshError):
        multires.icosphere(20)


def test_gzip_written_is_gzip(tmp_path, sphere):
    sphere.write(tmp_path / "s.obj.gz")
    with gzip.open(tmp_path / "s.obj.gz", "rt") as f:
        assert any(line.startswith("v ") for line in f)


def test_surface_distance_of_a_scaled_sphere():
    """Two concentric spheres 0.1 apart (up to the facets), the same figures on a second
    call, zero against itself, refusals for an empty sampling."""
    a = multires.icosphere(4)
    b = multires.Mesh.from_arrays(a.vertices * 1.1, a.faces)
    d = multires.surface_distance(a, b)
    for side in ("a_to_b", "b_to_a"):
        assert abs(d[side]["mean"] - 0.1) < 5e-3
        assert d[side]["max"] <= 0.1 + 1e-9
        assert d[side]["samples"] == a.n_vertices + 100000
    assert d == multires.surface_distance(a, b)
    assert abs(d["diagonal"] - 2 * 3 ** 0.5) < 2e-2
    assert multires.surface_distance(a, a, samples=1000)["hausdorff"] < 1e-12
    with pytest.raises(MeshError, match="neither"):
        multires.surface_distance(a, b, samples=0, vertices=False)
    with pytest.raises(MeshError, match="at most"):
        multires.surface_distance(a, b, samples=2**40)
