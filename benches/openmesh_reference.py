#!/usr/bin/env python3
"""OpenMesh (pip openmesh==1.2.1, C++ underneath) on the work of `cargo bench --bench kernel`,
so the figures can be put side by side. Run the Rust bench first: it writes the
1.6 M-face PLY into bench-cache/.

    python3 benches/openmesh_reference.py

Times are the minimum and median of several runs, in milliseconds:
- read_trimesh of bench-cache/nefertiti-subdivided-2.ply (binary PLY, 1.6 M faces) and of
  the bunny OBJ (parse + build, like `load …` in the Rust bench; OpenMesh has no separate
  "build from arrays" step to time from Python);
- update_normals (face and vertex normals, as the Rust `vertex_normals` computes both)
  and update_vertex_normals alone, on both meshes.
One-ring circulation over all vertices is not timed: a Python loop over OpenMesh's
circulators measures the interpreter, not OpenMesh.
"""

import os
import statistics
import sys
import time

import openmesh

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def shared_meshes():
    if "MULTIRES_MESHES" in os.environ:
        return os.environ["MULTIRES_MESHES"]
    d = ROOT
    while True:
        candidate = os.path.join(d, "shared", "meshes")
        if os.path.isdir(candidate):
            return candidate
        parent = os.path.dirname(d)
        if parent == d:
            sys.exit("no shared/meshes directory above the workspace (set MULTIRES_MESHES)")
        d = parent


def timed(label, work, runs):
    times = []
    for _ in range(runs):
        t = time.perf_counter()
        result = work()
        times.append(1e3 * (time.perf_counter() - t))
        del result  # freed outside the timed span, as criterion's iter_with_large_drop
    print(f"{label:55s} min {min(times):9.1f} ms   median {statistics.median(times):9.1f} ms")


def main():
    big = os.path.join(ROOT, "bench-cache", "nefertiti-subdivided-2.ply")
    if not os.path.exists(big):
        sys.exit(f"{big} is missing: run `cargo bench --bench kernel` first")
    bunny = os.path.join(shared_meshes(), "stanford-bunny.obj")

    timed("load bunny OBJ (read_trimesh)", lambda: openmesh.read_trimesh(bunny), 10)
    timed("load nefertiti x2 binary PLY (read_trimesh)", lambda: openmesh.read_trimesh(big), 10)
    for name, path in [("bunny", bunny), ("nefertiti x2", big)]:
        mesh = openmesh.read_trimesh(path)
        mesh.request_face_normals()
        mesh.request_vertex_normals()
        timed(f"update_normals {name} (face + vertex)", mesh.update_normals, 10)
        timed(f"update_vertex_normals {name}", mesh.update_vertex_normals, 10)


if __name__ == "__main__":
    main()
