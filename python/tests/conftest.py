"""Shared fixtures: generated meshes (the default tier) and the shared real meshes (the
``realmesh`` tier, found through ``MULTIRES_MESHES=DIR`` or the first ancestor folder
holding ``shared/meshes``)."""

import os
from pathlib import Path

import numpy as np
import pytest

import multires


def shared_meshes_dir():
    env = os.environ.get("MULTIRES_MESHES")
    if env:
        return Path(env)
    here = Path(__file__).resolve()
    for parent in here.parents:
        candidate = parent / "shared" / "meshes"
        if candidate.is_dir():
            return candidate
    return None


def real_meshes():
    d = shared_meshes_dir()
    if d is None or not d.is_dir():
        return []
    return sorted(p for p in d.iterdir() if multires_readable(p.name))


def multires_readable(name):
    name = name.lower()
    return any(name.endswith(e) for e in (".obj", ".ply", ".off", ".stl", ".obj.gz",
                                          ".ply.gz", ".off.gz", ".stl.gz"))


def pytest_collection_modifyitems(config, items):
    if shared_meshes_dir() is not None:
        return
    skip = pytest.mark.skip(reason="no shared meshes: set MULTIRES_MESHES=DIR or lay "
                                   "shared/meshes in an ancestor folder")
    for item in items:
        if "realmesh" in item.keywords:
            item.add_marker(skip)


def bumpy_sphere(level=4, seed=0):
    """An icosphere with a deterministic radial bump (so the rounds' planarity test
    has something to keep)."""
    m = multires.icosphere(level)
    v = m.vertices
    r = 1.0 + 0.05 * np.sin(5 * v[:, 0]) * np.cos(3 * v[:, 1] + seed)
    m.vertices = v * r[:, None]
    return m


@pytest.fixture
def sphere():
    return bumpy_sphere(4)


@pytest.fixture
def torus():
    return multires.torus(1.0, 0.35, 48, 24)


@pytest.fixture
def grid():
    return multires.grid(20, 14, 2.0, 1.4)


@pytest.fixture
def hierarchy(sphere):
    return multires.Hierarchy(sphere, target_faces=300)
