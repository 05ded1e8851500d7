"""Topology against OpenMesh in the same process: the same arrays (or the same file)
give the same vertex, face, edge and boundary counts and the same face-vertex lists."""

import numpy as np
import pytest

import multires
from conftest import bumpy_sphere, real_meshes

om = pytest.importorskip("openmesh", reason="pip install openmesh==1.2.1 for the OpenMesh tier")


def om_counts(m):
    boundary = sum(1 for h in m.halfedges() if m.is_boundary(h))
    loops, seen = 0, set()
    for h in m.halfedges():
        if m.is_boundary(h) and h.idx() not in seen:
            loops += 1
            g = h
            while g.idx() not in seen:
                seen.add(g.idx())
                g = m.next_halfedge_handle(g)
    return {"vertices": m.n_vertices(), "faces": m.n_faces(), "edges": m.n_edges(),
            "boundary_halfedges": boundary, "boundary_loops": loops}


def our_counts(mesh):
    i = mesh.info()
    # every boundary halfedge sits on one boundary vertex's loop
    return {"vertices": i["vertices"], "faces": i["faces"], "edges": i["edges"],
            "boundary_halfedges": i["boundary_vertices"] if i["non_manifold_vertices"] == 0 else None,
            "boundary_loops": i["boundary_loops"]}


def generated():
    two = multires.Mesh.from_arrays(
        np.vstack([multires.icosphere(1).vertices, multires.icosphere(1).vertices + 3]),
        np.vstack([multires.icosphere(1).faces, multires.icosphere(1).faces + 42]))
    return {
        "sphere": bumpy_sphere(3),
        "torus": multires.torus(1.0, 0.3, 24, 12),
        "grid": multires.grid(9, 7),
        "two_spheres": two,
    }


@pytest.mark.parametrize("name", ["sphere", "torus", "grid", "two_spheres"])
def test_same_topology_as_openmesh_from_arrays(name):
    mesh = generated()[name]
    v, f = mesh.vertices, mesh.faces
    theirs = om.TriMesh(v, f.astype(np.int32))
    ours = our_counts(mesh)
    t = om_counts(theirs)
    for key in ("vertices", "faces", "edges", "boundary_loops"):
        assert ours[key] == t[key], key
    if ours["boundary_halfedges"] is not None:
        assert ours["boundary_halfedges"] == t["boundary_halfedges"]
    assert np.array_equal(theirs.face_vertex_indices(), f)
    assert np.array_equal(theirs.points(), v)


@pytest.mark.parametrize("ext", ["obj", "off", "ply", "stl"])
def test_same_topology_as_openmesh_from_files(tmp_path, ext):
    mesh = generated()["torus"]
    path = tmp_path / f"torus.{ext}"
    mesh.write(path)
    theirs = om.read_trimesh(str(path))
    ours = multires.read(path, weld="off")
    t = om_counts(theirs)
    assert (ours.n_vertices, ours.n_faces, ours.n_edges) == (t["vertices"], t["faces"], t["edges"])
    assert ours.info()["boundary_loops"] == t["boundary_loops"]
    if ext != "stl":
        assert np.array_equal(theirs.face_vertex_indices(), ours.faces)


def test_hierarchy_levels_are_valid_openmesh_meshes(sphere):
    h = multires.Hierarchy(sphere, target_faces=300)
    for level in range(h.coarsest_level, -1, -1):
        h.go_to_level(level)
        m = h.mesh
        theirs = om.TriMesh(m.vertices, m.faces.astype(np.int32))
        t = om_counts(theirs)
        assert (t["vertices"], t["faces"], t["edges"]) == (m.n_vertices, m.n_faces, m.n_edges)
        assert t["boundary_loops"] == 0


@pytest.mark.realmesh
@pytest.mark.parametrize("path", real_meshes() or [None], ids=lambda p: p.name if p else "none")
def test_real_meshes_same_topology_as_openmesh(path):
    if path is None:
        pytest.skip("no shared meshes found")
    theirs = om.read_trimesh(str(path))
    ours = multires.read(path, weld="off")
    ours.check()
    t = om_counts(theirs)
    assert (ours.n_vertices, ours.n_faces, ours.n_edges) == (t["vertices"], t["faces"], t["edges"])
    if path.suffix.lower() != ".stl":
        assert np.array_equal(theirs.face_vertex_indices(), ours.faces)
    # and the same arrays give OpenMesh the same mesh again
    again = om.TriMesh(ours.vertices, ours.faces.astype(np.int32))
    assert om_counts(again)["edges"] == ours.n_edges
