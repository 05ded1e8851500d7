#!/usr/bin/env python3
"""Edge collapses and vertex splits with OpenMesh, for tests/openmesh_collapse.rs.

Usage:
  collapse.py ok FILE
      For every halfedge of FILE as `openmesh.read_trimesh` loads it, prints one line
      `FROM TO OK`: its from- and to-vertex indices and 1 when `is_collapse_ok` accepts it.
  collapse.py replay FILE SEQUENCE
      Replays a sequence of operations given by vertex indices of FILE, one per line:
        c FROM TO                 collapse the halfedge FROM -> TO
        s X Y Z V0 V1 VL VR W     vertex_split(point (X, Y, Z), V1, VL, VR); V0 is the
                                  index the re-inserted vertex has in the caller's mesh,
                                  -1 stands for a missing VL or VR; W (or -1) names the
                                  boundary gap of V1 to split at when VL or VR is missing
      and prints two JSON reports (one per line): after the collapses, and after the
      collapses and the splits. Each report is taken after `garbage_collection` on a mesh
      of its own (the collapses are replayed twice), so that the vertex indices of the
      sequence stay valid while replaying. A collapse OpenMesh refuses is an error (exit
      status 2, message on stderr).

The OpenMesh python bindings (pip package openmesh==1.2.1) always carry the status
attributes that collapses need, so no request_*_status call exists or is needed.
OpenMesh's `vertex_split` without VL or VR splits V1 at the boundary gap just before
`halfedge_handle(V1)`; when V1 has several boundary gaps (two boundary loops touching
at V1, which collapses can create), that is ambiguous, so the caller names the gap by
the vertex W that V1's boundary halfedge leads to, and V1's halfedge handle is set to
that halfedge first (the collapse record knows the gap, OpenMesh's arguments do not).

Report keys: vertices, edges, faces, halfedges, boundary_vertices, boundary_loops,
components, euler, valence_histogram (tests/openmesh/common.py, as report.py).
"""

import json
import sys

import numpy as np
import openmesh

from common import topology_report as report


def collapse_ok(path):
    mesh = openmesh.read_trimesh(path)
    hv = mesh.halfedge_vertex_indices()
    out = []
    for h in mesh.halfedges():
        a, b = hv[h.idx()]
        out.append(f"{a} {b} {int(mesh.is_collapse_ok(h))}")
    sys.stdout.write("\n".join(out))
    sys.stdout.write("\n")


def vertex(index):
    return openmesh.VertexHandle(int(index))


def apply_collapses(mesh, collapses):
    for step, (a, b) in enumerate(collapses):
        h = mesh.find_halfedge(vertex(a), vertex(b))
        if not h.is_valid():
            sys.stderr.write(f"collapse {step}: no halfedge {a} -> {b}\n")
            sys.exit(2)
        if not mesh.is_collapse_ok(h):
            sys.stderr.write(f"collapse {step}: OpenMesh refuses to collapse {a} -> {b}\n")
            sys.exit(2)
        mesh.collapse(h)


def replay(path, sequence):
    collapses, splits = [], []
    with open(sequence) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "c":
                collapses.append((int(parts[1]), int(parts[2])))
            elif parts[0] == "s":
                x, y, z = (float(p) for p in parts[1:4])
                v0, v1, vl, vr, w = (int(p) for p in parts[4:9])
                splits.append((np.array([x, y, z]), v0, v1, vl, vr, w))
            else:
                sys.exit(f"unknown operation {parts[0]!r}")

    coarse = openmesh.read_trimesh(path)
    apply_collapses(coarse, collapses)
    coarse.garbage_collection()
    print(json.dumps(report(coarse)), flush=True)

    mesh = openmesh.read_trimesh(path)
    apply_collapses(mesh, collapses)
    # Re-inserted vertices get new indices in OpenMesh; map the caller's indices to them.
    index = {}

    def handle(i):
        return vertex(index.get(i, i)) if i >= 0 else openmesh.VertexHandle(-1)

    for point, v0, v1, vl, vr, w in splits:
        if w >= 0:
            gap = mesh.find_halfedge(handle(v1), handle(w))
            if not (gap.is_valid() and mesh.is_boundary(gap)):
                sys.stderr.write(f"split of {v1}: no boundary halfedge {v1} -> {w}\n")
                sys.exit(2)
            mesh.set_halfedge_handle(handle(v1), gap)
        h = mesh.vertex_split(point, handle(v1), handle(vl), handle(vr))
        index[v0] = mesh.from_vertex_handle(h).idx()
    mesh.garbage_collection()
    print(json.dumps(report(mesh)), flush=True)


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "ok":
        collapse_ok(sys.argv[2])
    elif len(sys.argv) == 4 and sys.argv[1] == "replay":
        replay(sys.argv[2], sys.argv[3])
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
