"""Every editing method: on a Mesh and on a Hierarchy at a coarse level, against the
same edit made by the Rust recipe engine (bit for bit), against analytic results
(rigid motions, scalings), and every refusal."""

import numpy as np
import pytest

import multires
from multires import EditError, MeshError


def rows_toml(rows):
    return "[" + ", ".join(str(int(i)) for i in rows) + "]"


def vec_toml(v):
    return "[" + ", ".join(repr(float(x)) for x in v) + "]"


def matrix_toml(m):
    return "[" + ", ".join(vec_toml(r) for r in m) + "]"


def rot_z(degrees, centre=(0.0, 0.0, 0.0)):
    t = np.radians(degrees)
    c, s = np.cos(t), np.sin(t)
    m = np.eye(4)
    m[:2, :2] = [[c, -s], [s, c]]
    centre = np.asarray(centre)
    m[:3, 3] = centre - m[:3, :3] @ centre
    return m


def both_targets(sphere):
    """(python target, recipe target, numbering) pairs: a Mesh at level 0 and a
    Hierarchy at its coarsest level (recipe indices are input indices there)."""
    h = multires.Hierarchy(sphere, target_faces=400)
    return [
        ("mesh", sphere.copy(), sphere.copy(), np.arange(sphere.n_vertices)),
        ("hierarchy", h, h.copy(), h.input_indices),
    ]


def result(target):
    if isinstance(target, multires.Hierarchy):
        return target.copy().refine()
    return target


def same(a, b):
    ra, rb = result(a), result(b)
    assert ra.vertices.tobytes() == rb.vertices.tobytes()
    assert np.array_equal(ra.faces, rb.faces)


def level_of(target):
    return target.level if isinstance(target, multires.Hierarchy) else 0


# ---- bit-for-bit against the Rust recipe engine --------------------------------------

@pytest.mark.parametrize("method", ["pull", "scale", "rotate", "taper", "twist"])
def test_submesh_edits_match_the_recipe_engine(sphere, method):
    for name, ours, theirs, numbering in both_targets(sphere):
        v = ours.vertices
        rows = np.flatnonzero(v[:, 2] > 0.45)
        region = f'region = {{ kind = "vertices", indices = {rows_toml(numbering[rows])} }}'
        common = f"level = {level_of(ours)}\n{region}\npropagation = 2\n"
        axis = ([0.0, 0.0, 0.5], [0.0, 0.3, 1.0])
        axis_toml = f"axis = {{ point = {vec_toml(axis[0])}, direction = {vec_toml(axis[1])} }}"
        if method == "pull":
            multires.submesh_pull(ours, rows, [0.0, 0.05, 0.1], propagation=2)
            extra = "offset = [0.0, 0.05, 0.1]"
        elif method == "scale":
            multires.submesh_scale(ours, rows, 1.3, propagation=2)
            extra = "factor = 1.3"
        elif method == "rotate":
            multires.submesh_rotate(ours, rows, 20.0, axis=axis, propagation=2)
            extra = f"degrees = 20.0\n{axis_toml}"
        elif method == "taper":
            multires.submesh_taper(ours, rows, 0.6, propagation=2)
            extra = "factor = 0.6"
        else:
            multires.submesh_twist(ours, rows, 30.0, axis=axis, propagation=2)
            extra = f"degrees = 30.0\n{axis_toml}"
        recipe = f'version = 1\n[[step]]\nmethod = "{method}"\n{common}{extra}\n'
        out = multires.apply_recipe(theirs, recipe)
        assert out[0]["moved"] > 0, name
        assert not np.array_equal(result(ours).vertices, sphere.vertices), name
        same(ours, theirs)


@pytest.mark.parametrize("distance,shape", [("geodesic", "smoothstep"), ("euclidean", "linear"),
                                            ("geodesic", "smootherstep")])
def test_blend_matches_the_recipe_engine(sphere, distance, shape):
    for name, ours, theirs, numbering in both_targets(sphere):
        v = ours.vertices
        handle = np.flatnonzero(v[:, 2] > 0.7)
        fixed = v[:, 2] < -0.2  # a mask
        a = rot_z(25.0, centre=v[handle].mean(axis=0))
        a[:3, 3] += [0.0, 0.1, 0.05]
        report = multires.blend(ours, handle, fixed, a, distance=distance, shape=shape)
        assert report["handle"] == len(handle) and report["deformable"] > 0
        recipe = (
            'version = 1\n[[step]]\nmethod = "blend"\n'
            f"level = {level_of(ours)}\n"
            f'handle = {{ kind = "vertices", indices = {rows_toml(numbering[handle])} }}\n'
            f'fixed = {{ kind = "vertices", indices = {rows_toml(numbering[np.flatnonzero(fixed)])} }}\n'
            f"transform = {matrix_toml(a)}\n"
            f'distance = "{distance}"\nshape = "{shape}"\n'
        )
        multires.apply_recipe(theirs, recipe)
        same(ours, theirs)


def test_lee_drag_matches_the_recipe_engine(sphere):
    for name, ours, theirs, numbering in both_targets(sphere):
        v = ours.vertices
        top = int(np.argmax(v[:, 2]))
        area = np.flatnonzero(v[:, 2] > 0.5)
        n = multires.lee_drag(ours, [top], [0.0, 0.0, 0.15], area=area, scale=0.5)
        assert n > 0
        recipe = (
            'version = 1\n[[step]]\nmethod = "lee_drag"\n'
            f"level = {level_of(ours)}\n"
            f'area = {{ kind = "vertices", indices = {rows_toml(numbering[area])} }}\n'
            f"primitive = [{{ vertex = {int(numbering[top])} }}]\n"
            "pull = [0.0, 0.0, 0.15]\nscale = 0.5\n"
        )
        multires.apply_recipe(theirs, recipe)
        same(ours, theirs)


def test_lee_drag_disk_matches_a_disk_area(sphere):
    a, b = sphere.copy(), sphere.copy()
    top = int(np.argmax(sphere.vertices[:, 2]))
    multires.lee_drag(a, [top], [0.0, 0.0, 0.1], disk=(top, 120))
    recipe = ('version = 1\n[[step]]\nmethod = "lee_drag"\n'
              f'area = {{ kind = "disk", around = {{ vertex = {top} }}, vertices = 120 }}\n'
              "pull = [0.0, 0.0, 0.1]\n")
    multires.apply_recipe(b, recipe)
    same(a, b)
    d = multires.disk(sphere, top, 120)
    assert len(d) >= 120 and top in d


# ---- analytic results -------------------------------------------------------------------

def test_barr_twist_of_everything_beyond_the_ramp_is_a_rotation(sphere):
    m = sphere.copy()
    multires.barr_twist(m, [0, 0, 0], [0, 0, 1], -10.0, -5.0, 30.0)
    expected = sphere.vertices @ rot_z(30.0)[:3, :3].T
    assert np.allclose(m.vertices, expected, atol=1e-14, rtol=0)


def test_barr_taper_beyond_the_ramp_scales_across_the_axis(sphere):
    m = sphere.copy()
    multires.barr_taper(m, [0, 0, 0], [0, 0, 1], -10.0, -5.0, 0.5)
    expected = sphere.vertices * [0.5, 0.5, 1.0]
    assert np.allclose(m.vertices, expected, atol=1e-15, rtol=0)


def test_barr_bend_rate_zero_is_identity_and_vertices_limit_it(sphere):
    m = sphere.copy()
    multires.barr_bend(m, [0, 0, 0], [0, 0, 1], [1, 0, 0], 0.0)
    assert np.array_equal(m.vertices, sphere.vertices)
    some = np.flatnonzero(sphere.vertices[:, 2] > 0.3)
    multires.barr_bend(m, [0, 0, 0], [0, 0, 1], [1, 0, 0], 0.8, vertices=some)
    changed = np.any(m.vertices != sphere.vertices, axis=1)
    assert changed[some].any() and not changed[np.setdiff1d(np.arange(len(changed)), some)].any()


@pytest.mark.parametrize("kind", ["twist", "taper", "bend"])
def test_barr_on_a_hierarchy_refines_to_the_same_deformation_of_the_input(sphere, kind):
    """A field mark: the coarse deformation comes back as the deformation of the
    input's own positions (within rounding), not an interpolation of it."""
    h = multires.Hierarchy(sphere, target_faces=400)
    direct = sphere.copy()
    for target in (h, direct):
        if kind == "twist":
            multires.barr_twist(target, [0, 0, 0], [0, 0, 1], -1.0, 1.0, 60.0)
        elif kind == "taper":
            multires.barr_taper(target, [0, 0, 0], [0, 0, 1], -1.0, 1.0, 0.4)
        else:
            multires.barr_bend(target, [0, 0, 0], [0, 0, 1], [1, 0, 0], 0.7)
    refined = h.refine()
    assert np.allclose(refined.vertices, direct.vertices, atol=1e-12, rtol=0)
    assert not np.allclose(refined.vertices, sphere.vertices)


def test_blend_moves_the_handle_rigidly_and_keeps_the_fixed_part(sphere):
    m = sphere.copy()
    v = sphere.vertices
    handle = np.flatnonzero(v[:, 2] > 0.7)
    fixed = np.flatnonzero(v[:, 2] < 0.0)
    t = np.eye(4)
    t[:3, 3] = [0.0, 0.0, 0.25]
    multires.blend(m, handle, fixed, t[:3])  # a 3x4 matrix
    assert np.array_equal(m.vertices[handle], v[handle] + [0.0, 0.0, 0.25])
    assert m.vertices[fixed].tobytes() == v[fixed].tobytes()


def test_blend_on_a_hierarchy_carries_the_rigid_part_exactly(sphere):
    h = multires.Hierarchy(sphere, target_faces=400)
    level = h.level
    v = h.vertices
    handle = np.flatnonzero(v[:, 2] > 0.6)
    fixed = np.flatnonzero(v[:, 2] < -0.1)
    a = rot_z(40.0)
    multires.blend(h, handle, fixed, a)
    anc = h.ancestors(level)
    ids = h.input_indices
    full = h.refine()
    under_handle = np.isin(anc, ids[handle])
    under_fixed = np.isin(anc, ids[fixed])
    expected = sphere.vertices[under_handle] @ a[:3, :3].T
    assert np.allclose(full.vertices[under_handle], expected, atol=1e-13, rtol=0)
    assert full.vertices[under_fixed].tobytes() == sphere.vertices[under_fixed].tobytes()


def test_blend_refine_adds_vertices(sphere):
    for target in (sphere.copy(), multires.Hierarchy(sphere, target_faces=400)):
        v = target.vertices
        handle = np.flatnonzero(v[:, 2] > 0.7)
        fixed = np.flatnonzero(v[:, 2] < 0.2)
        t = np.eye(4)
        t[2, 3] = 0.8
        before = target.vertices.shape[0]
        r = multires.blend(target, handle, fixed, t, refine=0.05)
        assert r["new_vertices"] > 0
        if isinstance(target, multires.Hierarchy):
            # split at full resolution, the hierarchy rebuilt, back at its level
            assert target.level == target.coarsest_level or target.level is not None
            assert result(target).n_vertices == sphere.n_vertices + r["new_vertices"]
        else:
            assert target.vertices.shape[0] == before + r["new_vertices"]
        result(target).check()


def test_submesh_pull_translates_the_inside_and_keeps_far_vertices(sphere):
    m = sphere.copy()
    v = sphere.vertices
    region = np.flatnonzero(v[:, 2] > 0.5)
    multires.submesh_pull(m, region, [0.1, 0.0, 0.0], propagation=1)
    d = m.vertices - v
    far = v[:, 2] < 0.0
    assert d[far].tobytes() == np.zeros_like(d[far]).tobytes()
    inner = np.flatnonzero(v[:, 2] > 0.8)
    assert np.allclose(d[inner], [0.1, 0.0, 0.0], atol=1e-15)


def test_submesh_scale_about_a_centre(sphere):
    m = sphere.copy()
    v = sphere.vertices
    region = np.flatnonzero(v[:, 2] > 0.5)
    c = np.array([0.0, 0.0, 0.9])
    multires.submesh_scale(m, region, 2.0, centre=c, propagation=0)
    changed = np.any(m.vertices != v, axis=1)
    assert changed[v[:, 2] > 0.8].all()
    assert not changed[v[:, 2] < 0.4].any()
    # another centre, another result
    m2 = sphere.copy()
    multires.submesh_scale(m2, region, 2.0, propagation=0)
    assert not np.array_equal(m2.vertices, m.vertices)


def test_taubin_smooths_only_its_region(grid):
    v = grid.vertices
    bump = np.exp(-30 * ((v[:, 0] - 1.0) ** 2 + (v[:, 1] - 0.7) ** 2))
    v[:, 2] = bump * 0.3 + 0.01 * np.sin(40 * v[:, 0])
    grid.vertices = v
    region = np.hypot(v[:, 0] - 1.0, v[:, 1] - 0.7) < 0.4
    multires.taubin(grid, vertices=region, iterations=20)
    out = grid.vertices
    assert out[~region].tobytes() == v[~region].tobytes()
    assert np.abs(np.diff(out[region][:, 2])).sum() < np.abs(np.diff(v[region][:, 2])).sum()
    flat = multires.grid(5, 5)
    before = flat.vertices
    multires.taubin(flat, iterations=5, weights="cotangent")
    assert np.allclose(flat.vertices, before, atol=1e-15)


def test_taubin_on_a_hierarchy_keeps_what_it_did_not_touch(sphere):
    h = multires.Hierarchy(sphere, target_faces=400)
    level = h.level
    region = np.flatnonzero(h.vertices[:, 2] > 0.5)
    multires.taubin(h, vertices=region, iterations=5)
    anc = h.ancestors(level)
    outside = ~np.isin(anc, h.input_indices[region])
    full = h.refine()
    # fine vertices collapsed into an untouched coarse vertex are where they were
    touched_neighbourhood = np.any(full.vertices != sphere.vertices, axis=1)
    assert touched_neighbourhood.any()
    assert not np.any(touched_neighbourhood & outside & (sphere.vertices[:, 2] < 0.2))


def test_ffd_translate_moves_attached_vertices(sphere):
    m = sphere.copy()
    v = sphere.vertices
    n = multires.ffd(m, None, [0, -1.2, 0], [1, 0, 0], [0, 1, 0], translate=[0.0, 0.3, 0.0])
    assert n == sphere.n_vertices
    assert np.allclose(m.vertices, v + [0.0, 0.3, 0.0], atol=1e-9)
    h = multires.Hierarchy(sphere, target_faces=400)
    top = np.flatnonzero(h.vertices[:, 2] > 0.3)
    multires.ffd(h, top, [0, 0, 0.3], [1, 0, 0], [0, 0, 1], bend=0.4)
    full = h.refine()
    full.check()
    assert not np.array_equal(full.vertices, v)


def test_image_blend_identity_and_motion():
    h, w = 48, 64
    yy, xx = np.mgrid[0:h, 0:w]
    img = np.stack([(xx * 4) % 256, (yy * 5) % 256, (xx + yy) % 256], axis=-1).astype(np.uint8)
    handle = (np.abs(xx - 40) < 5) & (np.abs(yy - 24) < 5)
    fixed = (xx < 8) | (xx >= w - 4) | (yy < 4) | (yy >= h - 4)
    same_img = multires.blend_image(img, handle, fixed, np.eye(3))
    assert same_img.dtype == np.uint8 and same_img.shape == img.shape
    assert np.array_equal(same_img, img)
    t = np.array([[1.0, 0.0, 6.0], [0.0, 1.0, 0.0]])
    moved = multires.blend_image(img, handle, fixed, t, grid_step=2)
    assert not np.array_equal(moved, img)
    assert np.array_equal(moved[fixed & (xx < 4)], img[fixed & (xx < 4)])
    gray16 = (xx * 1000).astype(np.uint16)
    out16 = multires.blend_image(gray16, handle, fixed, t)
    assert out16.dtype == np.uint16 and out16.shape == gray16.shape
    with pytest.raises(MeshError, match="dtype"):
        multires.blend_image(img.astype(np.float32), handle, fixed, t)
    with pytest.raises(MeshError, match="shape"):
        multires.blend_image(img, handle[:10], fixed, t)
    with pytest.raises(EditError):
        multires.blend_image(img, handle, handle, t)


def test_polyline_blend_2d_and_3d():
    x = np.linspace(0.0, 10.0, 101)
    pts = np.stack([x, np.zeros_like(x)], axis=1)
    handle = np.flatnonzero(x > 8.0)
    fixed = x < 2.0
    t = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 1.0]])
    out = multires.blend_polyline(pts, handle, fixed, t)
    assert np.allclose(out[handle], pts[handle] + [0.0, 1.0], atol=1e-15)
    assert out[fixed].tobytes() == pts[fixed].tobytes()
    mid = out[(x > 2.0) & (x < 8.0)][:, 1]
    assert np.all(np.diff(mid) >= -1e-15) and 0 < mid.mean() < 1
    pts3 = np.stack([x, np.zeros_like(x), np.zeros_like(x)], axis=1)
    t3 = np.eye(4)
    t3[2, 3] = 2.0
    out3 = multires.blend_polyline(pts3, handle, fixed, t3, distance="euclidean", refine=0.05)
    assert out3.shape[0] > pts3.shape[0]
    with pytest.raises(MeshError, match="overlap"):
        multires.blend_polyline(pts, [1, 2], [2, 3], t)
    with pytest.raises(MeshError, match="matrix"):
        multires.blend_polyline(pts, handle, fixed, t3)


# ---- refusals --------------------------------------------------------------------------

def test_edit_refusals(sphere):
    m = sphere.copy()
    v = sphere.vertices
    handle = np.flatnonzero(v[:, 2] > 0.7)
    fixed = np.flatnonzero(v[:, 2] < 0.0)
    with pytest.raises(MeshError, match="out of range"):
        multires.blend(m, [sphere.n_vertices], fixed, np.eye(4))
    with pytest.raises(MeshError, match="out of range"):
        multires.blend(m, [-1], fixed, np.eye(4))
    with pytest.raises(MeshError, match="mask"):
        multires.blend(m, np.ones(5, dtype=bool), fixed, np.eye(4))
    with pytest.raises(MeshError, match="integer"):
        multires.blend(m, np.array([0.5]), fixed, np.eye(4))
    with pytest.raises(MeshError, match="4x4 or 3x4"):
        multires.blend(m, handle, fixed, np.eye(3))
    with pytest.raises(MeshError, match="last row"):
        multires.blend(m, handle, fixed, np.ones((4, 4)))
    bad = np.eye(4)
    bad[0, 3] = np.nan
    with pytest.raises(MeshError, match="not finite"):
        multires.blend(m, handle, fixed, bad)
    with pytest.raises(EditError):
        multires.blend(m, handle, handle, np.eye(4))
    with pytest.raises(MeshError, match="displacement"):
        multires.lee_drag(m, [0], [0, 0, np.inf], disk=(0, 50))
    with pytest.raises(MeshError, match="exactly one"):
        multires.lee_drag(m, [0], [0, 0, 1])
    with pytest.raises(MeshError, match="scale"):
        multires.lee_drag(m, [0], [0, 0, 1], disk=(0, 50), scale=2.0)
    with pytest.raises(MeshError, match="seed"):
        multires.lee_drag(m, [0], [0, 0, 1], disk=(10**7, 50))
    with pytest.raises(EditError):
        multires.lee_drag(m, [0], [0, 0, 1], area=np.arange(sphere.n_vertices))
    with pytest.raises(EditError):
        multires.barr_taper(m, [0, 0, 0], [0, 0, 0], 0.0, 1.0, 0.5)
    with pytest.raises(MeshError, match="three numbers"):
        multires.barr_taper(m, [0, 0], [0, 0, 1], 0.0, 1.0, 0.5)
    with pytest.raises(MeshError, match="falloff"):
        multires.submesh_pull(m, handle, [0, 0, 1], falloff="cubic")
    with pytest.raises(MeshError, match="weights"):
        multires.taubin(m, weights="heavy")
    with pytest.raises(TypeError, match="Mesh or multires.Hierarchy"):
        multires.taubin(np.zeros((3, 3)))
    assert m.vertices.tobytes() == sphere.vertices.tobytes(), "a refused edit changed the mesh"


def test_recipe_refusals(sphere, tmp_path):
    with pytest.raises(multires.RecipeError, match="version"):
        multires.apply_recipe(sphere, "version = 99\n")
    with pytest.raises(multires.RecipeError, match="bogus"):
        multires.apply_recipe(sphere, 'version = 1\n[[step]]\nmethod = "pull"\nbogus = 1\n')
    with pytest.raises(multires.RecipeError, match="level"):
        multires.apply_recipe(sphere, 'version = 1\n[[step]]\nmethod = "pull"\nlevel = 2\n'
                                      'region = { kind = "all" }\noffset = [0.0, 0.0, 1.0]\n')
    with pytest.raises(FileNotFoundError):
        multires.apply_recipe(sphere, str(tmp_path / "missing.toml"))
    p = tmp_path / "r.toml"
    p.write_text('version = 1\n[[step]]\nmethod = "scale"\nregion = { kind = "cut", axis = "+z", at = 0.7 }\n'
                 "factor = 1.2\n")
    out = multires.apply_recipe(sphere, str(p))
    assert out[0]["method"] == "scale" and out[0]["moved"] > 0


HOSTILE = {
    "no target faces": lambda s, h, f: multires.Hierarchy(s, target_faces=0),
    "NaN error bound": lambda s, h, f: multires.Hierarchy(s, max_error=float("nan")),
    "disk of the whole sphere": lambda s, h, f: multires.lee_drag(s, [0], [0, 0, .1], disk=(0, 10**9)),
    "empty primitive": lambda s, h, f: multires.lee_drag(s, [], [0, 0, .1], disk=(0, 50)),
    "FFD degree above count": lambda s, h, f: multires.ffd(s, None, [0, 0, 0], [1, 0, 0], [0, 1, 0], shape_grid=((9, 9), (2, 2))),
    "FFD empty grid": lambda s, h, f: multires.ffd(s, None, [0, 0, 0], [1, 0, 0], [0, 1, 0], shape_grid=((0, 0), (0, 0))),
    "FFD huge grid": lambda s, h, f: multires.ffd(s, None, [0, 0, 0], [1, 0, 0], [0, 1, 0], shape_grid=((3, 3), (10**6, 10**6))),
    "FFD frame with x along up": lambda s, h, f: multires.ffd(s, None, [0, 0, 0], [0, 1, 0], [0, 1, 0]),
    "FFD no vertices": lambda s, h, f: multires.ffd(s, [], [0, 0, 0], [1, 0, 0], [0, 1, 0]),
    "empty handle": lambda s, h, f: multires.blend(s, [], f, np.eye(4)),
    "empty sub-mesh": lambda s, h, f: multires.submesh_pull(s, [], [0, 0, 1]),
    "taper of 1e308": lambda s, h, f: multires.submesh_taper(s, h, 1e308),
    "NaN profile": lambda s, h, f: multires.barr_taper(s, [0, 0, 0], [0, 0, 1], 0, float("nan"), 2),
    "bend of 1e308": lambda s, h, f: multires.barr_bend(s, [0, 0, 0], [0, 0, 1], [1, 0, 0], 1e308),
    "NaN lambda": lambda s, h, f: multires.taubin(s, lambda_=float("nan")),
    "rotation without frontier": lambda s, h, f: multires.submesh_rotate(s, np.arange(s.n_vertices), 10),
    "picture grid step 0": lambda s, h, f: multires.blend_image(np.zeros((8, 8), np.uint8), np.eye(8, dtype=bool), np.arange(64).reshape(8, 8) == 63, np.eye(3), grid_step=0),
    "1x1 picture": lambda s, h, f: multires.blend_image(np.zeros((1, 1), np.uint8), np.ones((1, 1), bool), np.zeros((1, 1), bool), np.eye(3)),
    "empty polyline": lambda s, h, f: multires.blend_polyline(np.zeros((0, 2)), [], [], np.eye(3)),
    "welding tolerance 1e308": lambda s, h, f: s.welded(1e308),
    "garbage .mrh": lambda s, h, f: multires.Hierarchy.from_bytes(b"MRH\x00" * 100),
}


@pytest.mark.parametrize("case", sorted(HOSTILE))
def test_hostile_input_is_refused_or_done_never_a_panic(case, sphere):
    """Inputs at the edges (empty, NaN, 1e308, huge sizes): a MeshError (or a result
    whose positions are finite), never a Rust panic (PyO3's PanicException, a
    BaseException) or a crash."""
    v = sphere.vertices
    h = np.flatnonzero(v[:, 2] > 0.7)
    f = np.flatnonzero(v[:, 2] < 0.0)
    try:
        HOSTILE[case](sphere, h, f)
    except MeshError:
        pass
    assert np.isfinite(sphere.vertices).all()
