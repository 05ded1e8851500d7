"""Hierarchies: building, walking, refinement without edits bit for bit, set_vertices,
ancestors against records, .mrh files and bytes, pickling, progress, refusals."""

import pickle
import sys
import threading

import numpy as np
import pytest

import multires
from multires import MeshError


def test_build_levels_and_walks(sphere):
    h = multires.Hierarchy(sphere, target_faces=300)
    counts = h.level_face_counts
    assert counts[0] == sphere.n_faces and len(counts) == h.n_levels
    assert h.level == h.coarsest_level == h.n_levels - 1
    assert counts[-1] <= 600 and all(a > b for a, b in zip(counts, counts[1:]))
    assert h.faces.shape == (counts[-1], 3)
    h.go_to_level(1)
    assert h.level == 1 and h.mesh.n_faces == counts[1]
    h.mesh.check()
    assert h.method == "rounds"
    q = multires.Hierarchy(sphere, method="qem", target_faces=300)
    assert q.method == "qem" and q.level_face_counts[-1] <= 300


def test_refine_without_edits_restores_input_bit_for_bit(sphere, hierarchy):
    full = hierarchy.refine()
    assert hierarchy.level == 0
    assert full.vertices.tobytes() == sphere.vertices.tobytes()
    assert np.array_equal(full.faces, sphere.faces)


def test_bad_levels_and_options(hierarchy, sphere):
    for bad in (-1, hierarchy.coarsest_level + 1, 10**9):
        with pytest.raises(MeshError, match="level"):
            hierarchy.go_to_level(bad)
        with pytest.raises(MeshError, match="level"):
            hierarchy.ancestors(bad)
    with pytest.raises(MeshError, match="method"):
        multires.Hierarchy(sphere, method="fast")
    with pytest.raises(MeshError, match="detail"):
        multires.Hierarchy(sphere, detail="none")
    with pytest.raises(TypeError):
        multires.Hierarchy(np.zeros((3, 3)))


def test_input_indices_and_ancestors_agree_with_records(sphere):
    h = multires.Hierarchy(sphere, target_faces=300)
    rec = h.records()
    n = sphere.n_vertices
    assert len(rec["v0"]) == h.n_records
    assert rec["p0"].shape == (h.n_records, 3)
    assert np.all(np.diff(rec["level"]) >= 0) and rec["level"][-1] == h.coarsest_level
    # replay the collapses: parent[v0] = v1, level by level
    parent = np.arange(n)
    for level in range(1, h.coarsest_level + 1):
        for v0, v1 in zip(rec["v0"][rec["level"] == level], rec["v1"][rec["level"] == level]):
            parent[v0] = v1
        # follow chains to the root (a survivor may be removed later)
        root = parent.copy()
        while True:
            nxt = parent[root]
            if np.array_equal(nxt, root):
                break
            root = nxt
        assert np.array_equal(root, h.ancestors(level)), f"level {level}"
    assert np.array_equal(h.ancestors(0), np.arange(n))
    # the live vertices of the coarsest level are the ancestors' values
    assert np.array_equal(np.unique(h.ancestors(h.coarsest_level)), np.sort(h.input_indices))
    # a removed vertex that never survived an earlier collapse is where the input has
    # it (no edit yet; survivors move to their edge's midpoint)
    survived = set()
    fresh = []
    for k, (v0, v1) in enumerate(zip(rec["v0"], rec["v1"])):
        if v0 not in survived:
            fresh.append(k)
        survived.add(v1)
    fresh = np.array(fresh)
    assert len(fresh) > len(rec["v0"]) // 2
    assert np.array_equal(rec["p0"][fresh], sphere.vertices[rec["v0"][fresh]])


def test_set_vertices_moves_only_descendants(sphere):
    h = multires.Hierarchy(sphere, target_faces=300)
    level = h.coarsest_level
    v = h.vertices
    moved_rows = np.flatnonzero(v[:, 2] > 0.8)
    v[moved_rows] += [0.0, 0.0, 0.2]
    h.set_vertices(v)
    assert np.array_equal(h.vertices, v)
    moved_inputs = set(h.input_indices[moved_rows])
    anc = h.ancestors(level)
    full = h.refine()
    changed = np.any(full.vertices != sphere.vertices, axis=1)
    descendants = np.isin(anc, list(moved_inputs))
    assert changed.any()
    assert not np.any(changed & ~descendants), "a vertex whose ancestor stayed moved"
    with pytest.raises(MeshError, match="shape"):
        h.set_vertices(np.zeros((2, 3)))
    bad = h.vertices
    bad[0, 0] = np.nan
    with pytest.raises(MeshError):
        h.set_vertices(bad)


def test_save_load_round_trip_bit_exact(tmp_path, sphere):
    h = multires.Hierarchy(sphere, target_faces=300)
    h.go_to_level(2)
    v = h.vertices
    v[:10] *= 1.1
    h.set_vertices(v)
    h.save(tmp_path / "s.mrh")
    back = multires.Hierarchy.load(tmp_path / "s.mrh")
    assert back.level == 2 and back.level_face_counts == h.level_face_counts
    assert back.to_bytes() == h.to_bytes() == (tmp_path / "s.mrh").read_bytes()
    assert back.vertices.tobytes() == h.vertices.tobytes()
    a, b = h.refine(), back.refine()
    assert a.vertices.tobytes() == b.vertices.tobytes()
    assert np.array_equal(a.faces, b.faces)


def test_corrupt_and_missing_mrh(tmp_path, hierarchy):
    with pytest.raises(FileNotFoundError):
        multires.Hierarchy.load(tmp_path / "missing.mrh")
    data = bytearray(hierarchy.to_bytes())
    for where in (len(data) // 2, len(data) - 5, 3):
        bad = bytearray(data)
        bad[where] ^= 0xFF
        (tmp_path / "bad.mrh").write_bytes(bytes(bad))
        with pytest.raises(MeshError):
            multires.Hierarchy.load(tmp_path / "bad.mrh")
        with pytest.raises(MeshError):
            multires.Hierarchy.from_bytes(bytes(bad))
    (tmp_path / "short.mrh").write_bytes(bytes(data[:100]))
    with pytest.raises(MeshError):
        multires.Hierarchy.load(tmp_path / "short.mrh")
    with pytest.raises(MeshError):
        multires.Hierarchy.from_bytes(b"")


def test_pickle_round_trip(hierarchy, sphere):
    hierarchy.go_to_level(1)
    back = pickle.loads(pickle.dumps(hierarchy))
    assert back.level == 1
    assert back.to_bytes() == hierarchy.to_bytes()
    assert back.refine().vertices.tobytes() == sphere.vertices.tobytes()
    c = hierarchy.copy()
    c.go_to_level(0)
    assert hierarchy.level == 1


def test_progress_is_called_and_can_stop_the_build(sphere):
    calls = []
    multires.Hierarchy(sphere, target_faces=300, progress=lambda *a: calls.append(a))
    assert calls and all(c[2] == sphere.n_faces for c in calls)

    class Stop(Exception):
        pass

    def stop(levels, faces, total):
        raise Stop("enough")

    with pytest.raises(Stop, match="enough"):
        multires.Hierarchy(sphere, target_faces=300, progress=stop)


def test_info_of_a_hierarchy(hierarchy):
    i = hierarchy.info()
    assert i["hierarchy"]["levels"] == hierarchy.n_levels
    assert i["faces"] == hierarchy.level_face_counts[-1]


def ticks_during(call):
    """Runs `call` while another thread records time stamps; returns the stamps taken
    in the middle 60 % of the call and its duration."""
    import time
    stamps = []
    done = threading.Event()

    def count():
        while not done.is_set():
            stamps.append(time.perf_counter())

    t = threading.Thread(target=count)
    t.start()
    time.sleep(0.01)
    t0 = time.perf_counter()
    try:
        call()
    finally:
        t1 = time.perf_counter()
        done.set()
        t.join()
    lo, hi = t0 + 0.2 * (t1 - t0), t1 - 0.2 * (t1 - t0)
    return sum(lo < s < hi for s in stamps), t1 - t0


def test_long_calls_release_the_gil():
    """While one thread builds and walks a hierarchy in Rust, another runs Python: its
    time stamps fill the middle of the call (with the GIL held there would be none)."""
    mesh = multires.icosphere(6)
    n, seconds = ticks_during(lambda: multires.Hierarchy(mesh, target_faces=2000))
    assert seconds > 0.02 and n > 100, (n, seconds)
    h = multires.Hierarchy(mesh, target_faces=2000)
    n, seconds = ticks_during(lambda: h.go_to_level(0))
    assert n > 10, (n, seconds)


def test_workflow_job(tmp_path, sphere):
    sphere.write(tmp_path / "s.ply")
    mesh, steps = multires.workflow(tmp_path / "s.ply", level=2)
    names = [s["step"] for s in steps]
    assert "refine" in names and mesh.n_faces == sphere.n_faces
    assert all(set(s) == {"step", "detail", "seconds", "peak_bytes"} for s in steps)
    if sys.platform.startswith("linux"):
        ran = [s for s in steps if not s["detail"].startswith("skipped")]
        assert all(isinstance(s["peak_bytes"], int) and s["peak_bytes"] > 0 for s in ran)
    assert not np.array_equal(mesh.vertices, sphere.vertices)
    again, _ = multires.workflow(tmp_path / "s.ply", level=2)
    assert again.vertices.tobytes() == mesh.vertices.tobytes()
    with pytest.raises(FileNotFoundError):
        multires.workflow(tmp_path / "none.ply")
    with pytest.raises(MeshError, match="method"):
        multires.workflow(tmp_path / "s.ply", method="fast")


def test_ctrl_c_stops_a_build():
    """A pending KeyboardInterrupt (what Ctrl-C makes) stops a build at its next check
    (every level and every 65,536 collapses), well before the build would end."""
    import _thread
    import signal
    import time
    # interrupt_main does nothing while SIGINT is ignored or left to the system, as
    # something an earlier test ran (Dask's workers) may leave it: make it Python's.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        _interrupt_a_build(_thread, time)
    finally:
        signal.signal(signal.SIGINT, previous)


def _interrupt_a_build(_thread, time):
    mesh = multires.icosphere(7)
    t0 = time.perf_counter()
    multires.Hierarchy(mesh, target_faces=100)
    full = time.perf_counter() - t0
    if full < 0.2:
        pytest.skip(f"the build takes {full:.3f} s here: too fast to interrupt part-way")
    timer = threading.Timer(0.02, _thread.interrupt_main)
    t0 = time.perf_counter()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        multires.Hierarchy(mesh, target_faces=100)
        time.sleep(5)
    elapsed = time.perf_counter() - t0
    timer.cancel()
    # without the check the interrupt would only be seen after the whole build
    assert elapsed < 0.8 * full, (elapsed, full)


def test_threads_build_and_edit_in_parallel_with_serial_results():
    """Meshes edited from a thread pool (the GIL released in every call) end exactly
    as the same work done one after another."""
    from concurrent.futures import ThreadPoolExecutor

    from conftest import bumpy_sphere

    def job(seed):
        h = multires.Hierarchy(bumpy_sphere(4, seed=seed), target_faces=300)
        v = h.vertices
        multires.barr_twist(h, [0, 0, 0], [0, 0, 1], -1.0, 1.0, 10.0 * seed)
        multires.submesh_pull(h, np.flatnonzero(v[:, 2] > 0.5), [0.0, 0.0, 0.1])
        return h.refine().vertices.tobytes()

    serial = [job(s) for s in range(6)]
    with ThreadPoolExecutor(max_workers=3) as pool:
        parallel = list(pool.map(job, range(6)))
    assert parallel == serial


def test_rounds_placed_by_the_quadric(sphere):
    """placement="quadric": the same exact refinement, the coarse level nearer the input
    than the paper's midpoints (measured with surface_distance), bad names refused."""
    by_mid = multires.Hierarchy(sphere, target_faces=300)
    by_quad = multires.Hierarchy(sphere, target_faces=300, placement="quadric")
    near_mid = multires.surface_distance(sphere, by_mid.mesh, samples=20000)
    near_quad = multires.surface_distance(sphere, by_quad.mesh, samples=20000)
    assert near_quad["mean"] < near_mid["mean"]
    assert near_quad["hausdorff"] >= near_quad["a_to_b"]["mean"]
    fine = by_quad.refine()
    assert np.array_equal(fine.vertices, sphere.vertices)
    assert np.array_equal(fine.faces, sphere.faces)
    again = multires.Hierarchy.from_bytes(by_quad.to_bytes())
    assert np.array_equal(again.refine().vertices, sphere.vertices)
    with pytest.raises(MeshError, match="placement"):
        multires.Hierarchy(sphere, placement="centroid")
