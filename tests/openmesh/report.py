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

import openmesh

from common import topology_report


def report(path):
    return topology_report(openmesh.read_trimesh(path))


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for path in sys.argv[1:]:
        print(json.dumps(report(path)), flush=True)


if __name__ == "__main__":
    main()
