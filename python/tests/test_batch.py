"""Batches on Dask (a LocalCluster of two workers): the recipe, a Python function and
the workflow over a small corpus; rows as the Rust batch step writes them; resuming."""

import json
import os

import numpy as np
import pytest

import multires
from multires import MeshError
from conftest import bumpy_sphere

RECIPE = """version = 1
[hierarchy]
method = "rounds"
target_faces = 300

[[step]]
method = "scale"
level = 2
region = { kind = "cut", axis = "+z", at = 0.7 }
factor = 1.2
propagation = 1
"""


@pytest.fixture
def corpus(tmp_path):
    d = tmp_path / "in"
    (d / "sub").mkdir(parents=True)
    bumpy_sphere(3, seed=1).write(d / "a.obj")
    bumpy_sphere(3, seed=2).write(d / "sub" / "b.ply")
    multires.torus(1.0, 0.3, 32, 16).write(d / "c.off")
    (d / "broken.obj").write_text("v 0 0 0\nf 1 2 3\n")
    return d


def test_batch_step_rows_are_the_rust_rows(corpus, tmp_path):
    """The extension's per-mesh step is multires::batch::process: its row for a mesh
    is the row the command writes (same keys, statuses and hashes)."""
    out = tmp_path / "out"
    found = multires._multires._collect_inputs([str(corpus)])
    assert [r for _, r in found] == ["a.obj", "broken.obj", "c.off", os.path.join("sub", "b.ply")]
    rows = [json.loads(multires._multires._process(p, r, str(out), RECIPE)) for p, r in found]
    assert [r["status"] for r in rows] == ["ok", "error", "ok", "ok"]
    assert list(rows[0]) == ["input", "output", "status", "seconds", "faces", "vertices",
                             "error", "input_hash", "shard"]
    assert rows[1]["error"] and "broken.obj" in rows[1]["error"]
    assert os.path.isfile(out / "sub" / "b-edited.ply")
    again = [json.loads(multires._multires._process(p, r, str(out), RECIPE)) for p, r in found]
    assert [r["status"] for r in again] == ["skipped", "error", "skipped", "skipped"]
    (out / "a-edited.ply").write_bytes(b"cut")
    third = [json.loads(multires._multires._process(p, r, str(out), RECIPE)) for p, r in found]
    assert [r["status"] for r in third] == ["ok", "error", "skipped", "skipped"]
    rust_sidecar = json.loads((out / "a-edited.ply.json").read_text())
    assert list(rust_sidecar) == ["input", "input_hash", "job_hash", "output_hash", "faces", "vertices"]


def test_batch_without_dask_names_the_extra(monkeypatch, corpus, tmp_path):
    import builtins
    real_import = builtins.__import__

    def no_dask(name, *a, **k):
        if name.split(".")[0] in ("distributed", "dask"):
            raise ImportError(f"No module named {name!r}")
        return real_import(name, *a, **k)

    monkeypatch.setattr(builtins, "__import__", no_dask)
    with pytest.raises(ImportError, match=r"pip install multires\[dask\]"):
        multires.batch(str(corpus), tmp_path / "o")


def _edit(mesh):
    v = mesh.vertices
    multires.barr_twist(mesh, [0, 0, 0], [0, 0, 1], -1.0, 1.0, 20.0)
    assert not np.array_equal(v, mesh.vertices)
    return mesh


@pytest.mark.dask
def test_dask_batch_recipe_function_workflow_and_resume(corpus, tmp_path):
    pytest.importorskip("distributed", reason="pip install multires[dask] for the Dask batch test")
    import sys

    import cloudpickle
    import distributed

    # the workers cannot import this test module: send its functions by value
    cloudpickle.register_pickle_by_value(sys.modules[__name__])
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       dashboard_address=None)
    client = distributed.Client(cluster)
    try:
        assert len(client.scheduler_info()["workers"]) == 2
        out = tmp_path / "recipe"
        rows = multires.batch(str(corpus), out, recipe=RECIPE, client=client)
        assert [os.path.basename(r["input"]) for r in rows] == ["a.obj", "broken.obj", "c.off", "b.ply"]
        assert [r["status"] for r in rows] == ["ok", "error", "ok", "ok"]
        # identical to the extension's Rust step on the same inputs (but the timings)
        direct_out = tmp_path / "direct"
        found = multires._multires._collect_inputs([str(corpus)])
        direct = [json.loads(multires._multires._process(p, r, str(direct_out), RECIPE)) for p, r in found]
        strip = lambda r: {k: v for k, v in r.items() if k not in ("seconds", "output")}
        assert [strip(r) for r in rows] == [strip(r) for r in direct]
        a = multires.read(out / "a-edited.ply", weld="off")
        b = multires.read(direct_out / "a-edited.ply", weld="off")
        assert a.vertices.tobytes() == b.vertices.tobytes()
        report = [json.loads(l) for l in (out / "report.jsonl").read_text().splitlines()]
        assert sorted(r["input"] for r in report) == sorted(r["input"] for r in rows)
        summary = json.loads((out / "summary.json").read_text())
        assert (summary["meshes"], summary["ok"], summary["errors"]) == (4, 3, 1)
        # resumable: everything done is skipped, the report grows by one line per mesh
        rows2 = multires.batch(str(corpus), out, recipe=RECIPE, client=client)
        assert [r["status"] for r in rows2] == ["skipped", "error", "skipped", "skipped"]
        assert len((out / "report.jsonl").read_text().splitlines()) == 8

        fout = tmp_path / "function"
        frows = multires.batch(str(corpus), fout, function=_edit, client=client)
        assert [r["status"] for r in frows] == ["ok", "error", "ok", "ok"]
        assert all(r["input_hash"] == d["input_hash"] for r, d in zip(frows, direct))
        got = multires.read(fout / "c-edited.ply", weld="off")
        expect = multires.read(corpus / "c.off", weld="auto")
        _edit(expect)
        assert np.allclose(got.vertices, expect.vertices, atol=1e-12)
        frows2 = multires.batch(str(corpus), fout, function=_edit, client=client)
        assert [r["status"] for r in frows2] == ["skipped", "error", "skipped", "skipped"]
        # an output cut short since is made again (the sidecar records its hash)
        data = (fout / "c-edited.ply").read_bytes()
        (fout / "c-edited.ply").write_bytes(data[: len(data) // 2])
        frows3 = multires.batch(str(corpus), fout, function=_edit, client=client)
        assert [r["status"] for r in frows3] == ["skipped", "error", "ok", "skipped"]
        assert (fout / "c-edited.ply").read_bytes() == data
        sidecar = json.loads((fout / "c-edited.ply.json").read_text())
        assert list(sidecar) == ["input", "input_hash", "job_hash", "output_hash", "faces", "vertices"]

        # a scheduler address instead of a Client
        aout = tmp_path / "address"
        arows = multires.batch(str(corpus / "a.obj"), aout, recipe=RECIPE,
                               client=cluster.scheduler_address)
        assert [r["status"] for r in arows] == ["ok"]
        assert client.status == "running"

        # shards: two batches split the corpus with no coordinator
        parts = [multires.batch(str(corpus), tmp_path / "shards", recipe=RECIPE, client=client,
                                shard=f"{i}/2") for i in (1, 2)]
        inputs = sorted(r["input"] for part in parts for r in part)
        assert inputs == sorted(r["input"] for r in rows)
        assert all(r["shard"] == f"{i}/2" for i, part in zip((1, 2), parts) for r in part)
        for i in (1, 2):
            assert (tmp_path / "shards" / f"summary-{i}-of-2.json").is_file()
        fparts = [multires.batch(str(corpus), tmp_path / "fshards", function=_edit, client=client,
                                 shard=f" {i}/2") for i in (1, 2)]
        assert [[r["input"] for r in p] for p in fparts] == [[r["input"] for r in p] for p in parts]
        assert all(r["shard"] == f"{i}/2" for i, part in zip((1, 2), fparts) for r in part)
        with pytest.raises(MeshError, match="I/N"):
            multires.batch(str(corpus), tmp_path / "x", recipe=RECIPE, client=client, shard="3/2")

        wout = tmp_path / "workflow"
        wrows = multires.batch([str(corpus / "a.obj"), str(corpus / "c.off")], wout,
                               client=client, level=1)
        assert [r["status"] for r in wrows] == ["ok", "ok"], wrows
    finally:
        client.close()
        cluster.close()


def test_batch_refuses_a_bad_recipe_before_starting(corpus, tmp_path):
    pytest.importorskip("distributed")
    with pytest.raises(multires.RecipeError):
        multires.batch(str(corpus), tmp_path / "o", recipe="version = 7\n")
    with pytest.raises(ValueError, match="not both"):
        multires.batch(str(corpus), tmp_path / "o", recipe=RECIPE, function=_edit)


def _cli():
    import shutil
    from pathlib import Path
    env = os.environ.get("MULTIRES_BIN")
    if env and Path(env).is_file():
        return env
    root = Path(__file__).resolve().parents[2]
    for target in (os.environ.get("CARGO_TARGET_DIR"), root / "target"):
        if target and (Path(target) / "release" / "multires").is_file():
            return str(Path(target) / "release" / "multires")
    return shutil.which("multires")


def test_rows_and_outputs_match_the_multires_command(corpus, tmp_path):
    """The `multires batch` command and the package's Rust step on the same corpus:
    the same rows (but timings and output folders) and the same output bytes."""
    import subprocess
    cli = _cli()
    if cli is None:
        pytest.skip("no multires binary: cargo build --release --bin multires, or MULTIRES_BIN=PATH")
    (tmp_path / "r.toml").write_text(RECIPE)
    subprocess.run([cli, "batch", str(corpus), "--recipe", str(tmp_path / "r.toml"), "--out",
                    str(tmp_path / "cli")], capture_output=True)
    subprocess.run([cli, "batch", str(corpus), "--recipe", str(tmp_path / "r.toml"), "--out",
                    str(tmp_path / "cli-shard"), "--shard", "2/2"], capture_output=True)
    theirs = [json.loads(l) for l in (tmp_path / "cli-shard" / "report.jsonl").read_text().splitlines()]
    found = multires._multires._collect_inputs([str(corpus)], "2/2")
    ours = [json.loads(multires._multires._process(p, r, str(tmp_path / "py-shard"), RECIPE,
                                                   shard=(2, 2))) for p, r in found]
    strip = lambda r: {k: v for k, v in r.items() if k not in ("seconds", "output")}
    assert len(ours) >= 1 and all(r["shard"] == "2/2" for r in ours)
    assert sorted(map(json.dumps, map(strip, theirs))) == sorted(map(json.dumps, map(strip, ours)))
    theirs = [json.loads(l) for l in (tmp_path / "cli" / "report.jsonl").read_text().splitlines()]
    found = multires._multires._collect_inputs([str(corpus)])
    ours = [json.loads(multires._multires._process(p, r, str(tmp_path / "py"), RECIPE)) for p, r in found]
    strip = lambda r: {k: v for k, v in r.items() if k not in ("seconds", "output")}
    assert sorted(map(json.dumps, map(strip, theirs))) == sorted(map(json.dumps, map(strip, ours)))
    for name in ("a-edited.ply", "c-edited.ply", os.path.join("sub", "b-edited.ply")):
        assert (tmp_path / "cli" / name).read_bytes() == (tmp_path / "py" / name).read_bytes()


@pytest.mark.dask
def test_dask_batch_on_its_own_local_cluster(corpus, tmp_path):
    """No client: the batch starts a LocalCluster of two workers and closes it."""
    pytest.importorskip("distributed", reason="pip install multires[dask] for the Dask batch test")
    rows = multires.batch([str(corpus / "c.off"), str(corpus / "a.obj")], tmp_path / "o",
                          recipe=RECIPE, n_workers=2)
    assert [r["status"] for r in rows] == ["ok", "ok"]
    assert [os.path.basename(r["input"]) for r in rows] == ["a.obj", "c.off"]


def test_importing_multires_does_not_import_dask():
    import subprocess
    import sys
    code = "import sys, multires; print(any(m.split('.')[0] in ('dask', 'distributed') for m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd="/")
    assert out.stdout.strip() == "False", out.stdout + out.stderr
