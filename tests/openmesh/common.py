"""Topology report of an OpenMesh mesh, shared by report.py and collapse.py.

Report keys (as the `topology` example prints them): vertices, edges, faces, halfedges,
boundary_vertices, boundary_loops, components, euler, valence_histogram; see report.py
for their meaning.
"""

import numpy as np


def components(n_vertices, edge_vertices):
    parent = list(range(n_vertices))

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for a, b in edge_vertices:
        ra, rb = find(int(a)), find(int(b))
        if ra != rb:
            parent[ra] = rb
    return sum(1 for v in range(n_vertices) if find(v) == v)


def boundary_loops(mesh):
    face_of = mesh.halfedge_face_indices()
    boundary = np.nonzero(face_of < 0)[0] if mesh.n_halfedges() else []
    seen = set()
    loops = 0
    for start in boundary:
        start = int(start)
        if start in seen:
            continue
        loops += 1
        h = start
        while True:
            seen.add(h)
            h = mesh.next_halfedge_handle(mesh.halfedge_handle(h)).idx()
            if h == start:
                break
    return loops


def topology_report(mesh):
    """Topology report of a mesh without deleted elements."""
    nv, ne, nf = mesh.n_vertices(), mesh.n_edges(), mesh.n_faces()
    ev = mesh.edge_vertex_indices() if ne else np.zeros((0, 2), dtype=int)
    valence = np.bincount(ev.reshape(-1), minlength=nv) if nv else np.zeros(0, dtype=int)
    histogram = {}
    for val, count in zip(*np.unique(valence, return_counts=True)):
        histogram[str(int(val))] = int(count)
    return {
        "vertices": nv,
        "edges": ne,
        "faces": nf,
        "halfedges": mesh.n_halfedges(),
        "boundary_vertices": sum(1 for v in mesh.vertices() if mesh.is_boundary(v)),
        "boundary_loops": boundary_loops(mesh),
        "components": components(nv, ev),
        "euler": nv - ne + nf,
        "valence_histogram": histogram,
    }
