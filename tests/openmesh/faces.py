#!/usr/bin/env python3
"""The faces of mesh files as OpenMesh reads them.

Usage: faces.py FILE [FILE ...]

Prints one JSON object per file and line: {"vertices": number of vertices, "faces":
[[a, b, c], ...]}, the triangles in OpenMesh's face order, each rotated to start at its
smallest vertex index (so that the comparison does not depend on which halfedge a face
starts at). Read with `openmesh.read_trimesh` (pip package openmesh==1.2.1).
"""

import json
import sys

import openmesh


def canonical(face):
    k = face.index(min(face))
    return face[k:] + face[:k]


def faces(path):
    mesh = openmesh.read_trimesh(path)
    triangles = mesh.face_vertex_indices().tolist() if mesh.n_faces() else []
    return {
        "vertices": mesh.n_vertices(),
        "faces": [canonical([int(i) for i in t]) for t in triangles],
    }


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for path in sys.argv[1:]:
        print(json.dumps(faces(path)), flush=True)


if __name__ == "__main__":
    main()
