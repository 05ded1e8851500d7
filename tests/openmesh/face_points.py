#!/usr/bin/env python3
"""The faces of mesh files as OpenMesh reads them, by the positions of their corners.

Usage: face_points.py FILE [FILE ...]

Prints one JSON object per file and line: {"faces": [[[x, y, z], [x, y, z], [x, y, z]],
...]}, the triangles in OpenMesh's face order, each rotated to start at its smallest
corner (compared as (x, y, z)), so that the comparison depends neither on which
halfedge a face starts at nor on how vertices are numbered. For formats without file
vertices (STL), where OpenMesh numbers merged vertices its own way. Read with
`openmesh.read_trimesh` (pip package openmesh==1.2.1); coordinates are the floats
OpenMesh keeps.
"""

import json
import sys

import openmesh


def canonical(corners):
    k = corners.index(min(corners))
    return corners[k:] + corners[:k]


def face_points(path):
    mesh = openmesh.read_trimesh(path)
    points = mesh.points().tolist()
    triangles = mesh.face_vertex_indices().tolist() if mesh.n_faces() else []
    return {"faces": [canonical([points[int(i)] for i in t]) for t in triangles]}


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for path in sys.argv[1:]:
        print(json.dumps(face_points(path)), flush=True)


if __name__ == "__main__":
    main()
