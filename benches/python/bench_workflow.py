"""Simplify -> edit -> refine from Python against the same steps in Rust.

Python: ``multires.read`` -> ``Hierarchy`` -> ``apply_recipe`` (and, separately, the same
edit made with the array API: a region computed in NumPy and ``submesh_scale``) ->
``refine`` -> ``write``. Rust: the ``multires`` command's ``batch --recipe`` on the same
file with the same recipe (read, weld, build, edit, refine, write; plus the input's
BLAKE3 and a sidecar). Both weld ``auto``. Optional comparison rows: ``fast_simplification``
and ``pyfqmr`` decimating the same arrays to the same face count, when installed.

    python3 benches/python/bench_workflow.py [--level 7] [--bin PATH] [--shared] [--mesh FILE]

The Rust binary is taken from --bin, $MULTIRES_BIN, or built with
``cargo build --release --bin multires`` (CARGO_TARGET_DIR respected).
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

import multires

ROOT = Path(__file__).resolve().parents[2]

RECIPE = """version = 1
[hierarchy]
method = "rounds"
target_faces = {target}

[[step]]
method = "scale"
level = {level}
region = {{ kind = "cut", axis = "+z", at = 0.7 }}
factor = 1.2
propagation = 2
"""


def bumpy_sphere(level):
    m = multires.icosphere(level)
    v = m.vertices
    r = 1.0 + 0.05 * np.sin(5 * v[:, 0]) * np.cos(3 * v[:, 1])
    m.vertices = v * r[:, None]
    return m


def rust_binary(explicit):
    for candidate in (explicit, os.environ.get("MULTIRES_BIN")):
        if candidate and Path(candidate).is_file():
            return Path(candidate)
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    binary = target / "release" / "multires"
    if not binary.is_file():
        if shutil.which("cargo") is None:
            return None
        subprocess.run(["cargo", "build", "--release", "--bin", "multires"], cwd=ROOT, check=True)
    return binary


def timed(f):
    t = time.perf_counter()
    out = f()
    return out, time.perf_counter() - t


def python_run(path, recipe, target, level, out):
    steps = {}
    mesh, steps["read"] = timed(lambda: multires.read(path))
    h, steps["build"] = timed(lambda: multires.Hierarchy(mesh, target_faces=target))
    _, steps["edit"] = timed(lambda: multires.apply_recipe(h, recipe))
    full, steps["refine"] = timed(h.refine)
    _, steps["write"] = timed(lambda: full.write(out))
    return full, steps


def python_arrays_run(path, target, level, out):
    """The same edit through the array API (region computed in NumPy)."""
    steps = {}
    mesh, steps["read"] = timed(lambda: multires.read(path))
    h, steps["build"] = timed(lambda: multires.Hierarchy(mesh, target_faces=target))

    def edit():
        h.go_to_level(min(level, h.coarsest_level))
        v = h.vertices
        lo, hi = v[:, 2].min(), v[:, 2].max()
        region = v[:, 2] > lo + 0.7 * (hi - lo)
        multires.submesh_scale(h, region, 1.2, propagation=2)

    _, steps["edit"] = timed(edit)
    full, steps["refine"] = timed(h.refine)
    _, steps["write"] = timed(lambda: full.write(out))
    return full, steps


def rust_run(binary, path, recipe_path, out_dir):
    t = time.perf_counter()
    subprocess.run([str(binary), "batch", str(path), "--recipe", str(recipe_path), "--out",
                    str(out_dir)], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    return time.perf_counter() - t


def gil_probe(path, target):
    """Fraction of a hierarchy build during which another Python thread ran."""
    mesh = multires.read(path)
    stamps, done = [], threading.Event()

    def count():
        while not done.is_set():
            stamps.append(time.perf_counter())
            time.sleep(0.001)

    th = threading.Thread(target=count)
    th.start()
    t0 = time.perf_counter()
    multires.Hierarchy(mesh, target_faces=target)
    t1 = time.perf_counter()
    done.set()
    th.join()
    inside = [s for s in stamps if t0 < s < t1]
    gaps = np.diff([t0] + inside + [t1]) if inside else np.array([t1 - t0])
    return {"build_seconds": t1 - t0, "ticks_during_build": len(inside),
            "longest_gap_ms": float(gaps.max() * 1000)}


def comparison_rows(mesh, target):
    rows = {}
    v, f = mesh.vertices, mesh.faces
    try:
        import fast_simplification
        ratio = 1.0 - target / len(f)
        _, s = timed(lambda: fast_simplification.simplify(v.astype(np.float32), f.astype(np.int32), ratio))
        rows["fast_simplification.simplify"] = s
    except ImportError:
        rows["fast_simplification.simplify"] = None
    try:
        import pyfqmr
        def run():
            s = pyfqmr.Simplify()
            s.setMesh(v, f.astype(np.int32))
            s.simplify_mesh(target_count=target, aggressiveness=7, preserve_border=True, verbose=0)
            return s.getMesh()
        _, s = timed(run)
        rows["pyfqmr.simplify_mesh"] = s
    except ImportError:
        rows["pyfqmr.simplify_mesh"] = None
    _, s = timed(lambda: multires.Hierarchy(mesh, method="qem", target_faces=target))
    rows["multires.Hierarchy(qem)"] = s
    _, s = timed(lambda: multires.Hierarchy(mesh, method="rounds", target_faces=target))
    rows["multires.Hierarchy(rounds)"] = s
    return rows


def bench(path, binary, target, level, repeats, tmp):
    recipe = RECIPE.format(target=target, level=level)
    recipe_path = tmp / "recipe.toml"
    recipe_path.write_text(recipe)
    py_times, arr_times, rust_times, steps = [], [], [], None
    for k in range(repeats):
        full, steps = python_run(path, recipe, target, level, tmp / f"py{k}.ply")
        py_times.append(sum(steps.values()))
        _, s2 = python_arrays_run(path, target, level, tmp / f"arr{k}.ply")
        arr_times.append(sum(s2.values()))
        if binary is not None:
            out = tmp / f"rust{k}"
            rust_times.append(rust_run(binary, path, recipe_path, out))
            rust_mesh = multires.read(out / (Path(path).name.split(".")[0] + "-edited.ply"), weld="off")
            same = rust_mesh.vertices.tobytes() == full.vertices.tobytes()
            steps["identical_to_rust"] = same
    row = {
        "mesh": str(path), "faces": full.n_faces,
        "python_recipe_s": min(py_times), "python_arrays_s": min(arr_times),
        "python_steps_s": steps,
    }
    if rust_times:
        row["rust_cli_s"] = min(rust_times)
        row["python_over_rust"] = min(py_times) / min(rust_times)
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--level", type=int, default=7, help="icosphere level of the generated mesh (7: 327,680 faces)")
    ap.add_argument("--target", type=int, default=2000)
    ap.add_argument("--edit-level", type=int, default=3)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--bin", default=None)
    ap.add_argument("--shared", action="store_true", help="also the meshes of shared/meshes")
    ap.add_argument("--no-rust", action="store_true")
    ap.add_argument("--mesh", action="append", default=[], help="also this mesh file (repeatable), e.g. the bench cache's nefertiti x2 (cargo run --release --example bench_cache -- 2M)")
    a = ap.parse_args()
    binary = None if a.no_rust else rust_binary(a.bin)
    results = []
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        generated = tmp / "generated.ply"
        mesh = bumpy_sphere(a.level)
        mesh.write(generated)
        paths = [generated] + [Path(m) for m in a.mesh]
        if a.shared:
            for parent in ROOT.parents:
                shared = parent / "shared" / "meshes"
                if shared.is_dir():
                    paths += sorted(p for p in shared.iterdir() if p.suffix in (".obj", ".ply"))
                    break
        for p in paths:
            results.append(bench(p, binary, a.target, a.edit_level, a.repeats, tmp))
            print(json.dumps(results[-1]), flush=True)
        print(json.dumps({"gil": gil_probe(generated, a.target)}), flush=True)
        # the simplifier rows on the first --mesh given (the bench mesh), else the generated one
        compared = multires.read(str(a.mesh[0])) if a.mesh else mesh
        print(json.dumps({"simplifiers_s": comparison_rows(compared, a.target)}), flush=True)


if __name__ == "__main__":
    sys.exit(main())
