"""Corpus batches on Dask: the ``multires batch`` job (a recipe or the workflow) or a
Python function mapped over many meshes, resumable, writing the same ``report.jsonl``
rows and sidecars as the command line.

The per-mesh step of a recipe or the workflow is the Rust ``multires::batch::process``
itself (through the extension), so the rows are the command's rows, byte for byte apart
from the timings. Dask is imported only when a batch runs: the package works without it.
"""

from __future__ import annotations

import inspect
import json
import os
import time
from pathlib import Path
from typing import Any, Callable, Iterable, Optional, Union

from . import _multires

_DASK_HINT = "multires.batch runs on Dask: pip install multires[dask] (dask and distributed)"


def _import_distributed():
    try:
        import distributed  # noqa: F401
    except ImportError as e:  # pragma: no cover - exercised when dask is absent
        raise ImportError(_DASK_HINT) from e
    return distributed


def _row_json(row: dict) -> str:
    """A row as the command writes it (serde_json's compact form, its key order)."""
    keys = ["input", "output", "status", "seconds", "faces", "vertices", "error",
            "input_hash", "shard"]
    return json.dumps({k: row.get(k) for k in keys}, separators=(",", ":"),
                      ensure_ascii=False)


def _function_hash(function: Callable, fmt: str, weld: Any) -> str:
    name = f"{getattr(function, '__module__', '')}.{getattr(function, '__qualname__', repr(function))}"
    try:
        source = inspect.getsource(function)
    except (OSError, TypeError):
        source = ""
    return _multires._blake3_text(f"python {name}\n{source}|{fmt}|{weld!r}")


def _run_function(path: str, relative: str, out: str, function: Callable, fmt: str,
                  weld: Any, job_hash: str, shard: Optional[str]) -> str:
    """One mesh through a Python function: the row as JSON text (never raises for the
    mesh's own failure)."""
    clock = time.perf_counter()
    output = _multires._output_path(relative, out, fmt)
    row = {"input": path, "output": output, "status": "error", "seconds": 0.0,
           "faces": 0, "vertices": 0, "error": None, "input_hash": None, "shard": shard}
    sidecar = output + ".json"
    try:
        row["input_hash"] = _multires._blake3_file(path)
        if os.path.isfile(output) and os.path.isfile(sidecar):
            try:
                with open(sidecar, encoding="utf-8") as f:
                    previous = json.load(f)
            except (OSError, ValueError):
                previous = None
            if (previous and previous.get("input_hash") == row["input_hash"]
                    and previous.get("job_hash") == job_hash
                    and previous.get("output_hash") == _multires._blake3_file(output)):
                row.update(status="skipped", faces=previous.get("faces", 0),
                           vertices=previous.get("vertices", 0))
                row["seconds"] = time.perf_counter() - clock
                return _row_json(row)
        mesh = _multires.read(path, weld=weld)
        row["faces"], row["vertices"] = mesh.n_faces, mesh.n_vertices
        os.makedirs(os.path.dirname(output) or ".", exist_ok=True)
        if os.path.exists(sidecar):
            os.remove(sidecar)
        result = function(mesh)
        if result is None:
            result = mesh
        if not isinstance(result, _multires.Mesh):
            raise TypeError(f"the batch function returned {type(result).__name__}, "
                            "not a multires.Mesh (or None for the mesh edited in place)")
        result.write(output)
        with open(sidecar, "w", encoding="utf-8") as f:
            json.dump({"input": path, "input_hash": row["input_hash"],
                       "job_hash": job_hash, "output_hash": _multires._blake3_file(output),
                       "faces": row["faces"], "vertices": row["vertices"]}, f, indent=2)
        row["status"] = "ok"
    except Exception as e:  # noqa: BLE001 - one bad mesh never stops a batch
        row["error"] = f"{type(e).__name__}: {e}" if not isinstance(e, ValueError) else str(e)
    row["seconds"] = time.perf_counter() - clock
    return _row_json(row)


def _run_process(path: str, relative: str, out: str, recipe: Optional[str], fmt: str,
                 weld: Any, level: int, method: str, shard: Optional[tuple]) -> str:
    return _multires._process(path, relative, out, recipe, fmt, weld, level, method, shard)


def batch(
    inputs: Union[str, os.PathLike, Iterable[Union[str, os.PathLike]]],
    out_dir: Union[str, os.PathLike],
    recipe: Optional[str] = None,
    function: Optional[Callable[[Any], Any]] = None,
    client: Any = None,
    *,
    format: str = "ply",
    weld: Union[str, float] = "auto",
    level: int = 3,
    method: str = "rounds",
    n_workers: int = 2,
    shard: Optional[str] = None,
) -> list:
    """Runs a batch over many meshes on Dask and returns the report rows (dicts, input
    order).

    ``inputs`` are folders (searched recursively for .obj .ply .off .stl and their .gz),
    glob patterns, manifest files (.txt/.list/.lst) or mesh files, as for
    ``multires batch``. Each mesh is read (welded by ``weld``) and then:

    - ``recipe`` (a .toml path or TOML text): the recipe is applied, on a hierarchy when
      a step has a level, exactly as ``multires batch --recipe`` does;
    - ``function``: ``function(mesh)`` is called with the :class:`Mesh` and returns the
      edited mesh (or ``None`` when it edited ``mesh`` in place);
    - neither: the workflow (``level``, ``method``) as ``multires batch`` runs it.

    The output goes to ``out_dir/<relative path>-edited.<format>`` with a JSON sidecar
    recording the BLAKE3 of the input and of the output and the job's hash; a mesh whose
    output is up to date (same input, same job, output unchanged) is ``skipped``, so an
    interrupted batch resumes. Every mesh appends one line to
    ``out_dir/report.jsonl`` (``input``, ``output``, ``status`` ok|skipped|error,
    ``seconds``, ``faces``, ``vertices``, ``error``, ``input_hash``, ``shard``) and the
    batch writes ``out_dir/summary.json``. One bad mesh never stops a batch.

    ``client``: ``None`` starts a ``LocalCluster`` of ``n_workers`` workers (closed at
    the end), a string is a scheduler address, or a ``distributed.Client``. On a
    cluster, the input and output folders must be on a file system the workers share.

    ``shard="I/N"`` runs only that shard of the corpus, the command's deterministic split
    by path hash (rows say ``shard``; the summary is ``summary-I-of-N.json``): N batches,
    each with its own Dask cluster or client, share a corpus with no coordinator.

    Raises ImportError (``pip install multires[dask]``) when Dask is not installed.
    """
    distributed = _import_distributed()
    if recipe is not None and function is not None:
        raise ValueError("give a recipe or a function, not both")
    if isinstance(inputs, (str, os.PathLike)):
        inputs = [inputs]
    shard_pair = _multires._parse_shard(shard) if shard is not None else None
    shard_text = None if shard_pair is None else f"{shard_pair[0]}/{shard_pair[1]}"
    found = _multires._collect_inputs([os.fspath(i) for i in inputs], shard)
    out = os.fspath(out_dir)
    os.makedirs(out, exist_ok=True)
    recipe_text = None
    if recipe is not None:
        recipe = os.fspath(recipe)
        recipe_text = Path(recipe).read_text(encoding="utf-8") if (
            "\n" not in recipe and os.path.isfile(recipe)) else recipe
        # Refuse a bad recipe here, once, rather than once per mesh.
        _multires._job_hash(out, recipe_text, format, weld, level, method)
    else:
        _multires._job_hash(out, None, format, weld, level, method)

    own_client = None
    if client is None:
        cluster = distributed.LocalCluster(n_workers=n_workers, threads_per_worker=1,
                                           processes=True, dashboard_address=None)
        own_client = distributed.Client(cluster)
        client = own_client
    elif isinstance(client, str):
        own_client = distributed.Client(client)
        client = own_client
    clock = time.perf_counter()
    try:
        if function is not None:
            job_hash = _function_hash(function, format, weld)
            futures = [client.submit(_run_function, p, r, out, function, format, weld,
                                     job_hash, shard_text, pure=False) for p, r in found]
        else:
            futures = [client.submit(_run_process, p, r, out, recipe_text, format, weld,
                                     level, method, shard_pair, pure=False) for p, r in found]
        index = {f.key: k for k, f in enumerate(futures)}
        rows: list = [None] * len(futures)
        with open(os.path.join(out, "report.jsonl"), "a", encoding="utf-8") as report:
            for future in distributed.as_completed(futures):
                line = future.result()
                report.write(line + "\n")
                report.flush()
                rows[index[future.key]] = json.loads(line)
    finally:
        if own_client is not None:
            cluster = getattr(own_client, "cluster", None)
            own_client.close()
            if cluster is not None and client is own_client and own_client is not None:
                try:
                    cluster.close()
                except Exception:  # noqa: BLE001
                    pass
    summary = {
        "meshes": len(rows),
        "ok": sum(r["status"] == "ok" for r in rows),
        "skipped": sum(r["status"] == "skipped" for r in rows),
        "errors": sum(r["status"] == "error" for r in rows),
        "seconds": time.perf_counter() - clock,
        "faces": sum(r["faces"] for r in rows),
        "shard": shard_text,
    }
    name = ("summary.json" if shard_pair is None
            else f"summary-{shard_pair[0]}-of-{shard_pair[1]}.json")
    with open(os.path.join(out, name), "w", encoding="utf-8") as f:
        json.dump(summary, f, indent=2)
    return rows
