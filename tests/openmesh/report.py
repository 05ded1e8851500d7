#!/usr/bin/env python3
"""Topology report of mesh files as OpenMesh loads them.

Usage: report.py FILE [FILE ...]

Prints one JSON object per file and line, with the keys of the `topology` example
(`cargo run --release --example topology -- FILE`): vertices, edges, faces, halfedges,
boundary_vertices, boundary_loops, components, euler, valence_histogram. The mesh is
read with `openmesh.read_trimesh` (pip package openmesh==1.2.1), which keeps isolated
vertices and duplicates the vertices of faces that would make the mesh non-manifold.

- boundary_vertices: vertices on the boundary, isolated vertices included (OpenMesh's
  `is_boundary` is true for them);
- boundary_loops: closed loops of boundary halfedges (followed with `next`);
- components: connected components of the vertex-edge graph (union-find); an isolated
  vertex is a component of its own;
- euler: V - E + F;
- valence_histogram: {valence (string): number of vertices}; isolated vertices have 0.
"""

import json
import sys

import numpy as np
import openmesh


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


def report(path):
    mesh = openmesh.read_trimesh(path)
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


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for path in sys.argv[1:]:
        print(json.dumps(report(path)), flush=True)


if __name__ == "__main__":
    main()
