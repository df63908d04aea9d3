"""Scene.intersect: the same answer on any number of threads and for a ray cast
alone, and primitive ids that follow the order triangles, then spheres, whatever
order the BVH keeps."""

import numpy as np
import pytest

import ppm_core


def test_threads_and_primitive_ids():
    rng = np.random.default_rng(5)
    s = ppm_core.Scene()
    m = s.add_material("grey")
    n = 400  # a soup of small triangles, two meshes, then spheres
    centres = rng.uniform(-1, 1, size=(n, 3))
    corners = centres[:, None, :] + rng.normal(scale=0.08, size=(n, 3, 3))
    tris = np.arange(3 * n).reshape(n, 3)
    s.add_mesh("a", corners[: n // 2].reshape(-1, 3), tris[: n // 2], materials=m, object_id=1)
    s.add_mesh("b", corners[n // 2 :].reshape(-1, 3), tris[: n - n // 2], materials=m, object_id=2)
    for i, c in enumerate(rng.uniform(-1, 1, size=(20, 3))):
        s.add_sphere(f"s{i}", tuple(c), 0.05, m, object_id=10 + i)

    o = rng.normal(size=(20000, 3))
    o *= 3.0 / np.linalg.norm(o, axis=1)[:, None]
    d = rng.uniform(-1, 1, size=o.shape) - o
    one, two = s.intersect(o, d, threads=1), s.intersect(o, d, threads=2)
    for key in ("t", "normal", "primitive", "object"):
        np.testing.assert_array_equal(one[key], two[key])
    hit = one["primitive"] >= 0
    assert 0.2 < hit.mean() < 0.95
    prim, obj = one["primitive"][hit], one["object"][hit]
    assert ((prim < n // 2) == (obj == 1)).all()
    assert (((prim >= n // 2) & (prim < n)) == (obj == 2)).all()
    assert ((prim >= n) == (obj >= 10)).all()
    np.testing.assert_array_equal(obj[prim >= n], prim[prim >= n] - n + 10)

    # The reported triangle is really hit at t: the hit point lies in its plane.
    tri_hit = prim < n
    unit = d[hit][tri_hit] / np.linalg.norm(d[hit][tri_hit], axis=1)[:, None]
    p = o[hit][tri_hit] + one["t"][hit][tri_hit, None] * unit
    v0 = corners[prim[tri_hit], 0]
    nrm = np.cross(corners[prim[tri_hit], 1] - v0, corners[prim[tri_hit], 2] - v0)
    nrm /= np.linalg.norm(nrm, axis=1)[:, None]
    assert np.abs(np.einsum("ij,ij->i", p - v0, nrm)).max() < 1e-9



@pytest.mark.parametrize("layout", ["copies", "compact"])
def test_a_built_scene_keeps_its_triangles_once_and_gets_them_back_to_change(layout):
    """A built scene keeps its triangles' vertex indices in the BVH's leaf records only; adding a mesh
    after a build (and building again) must find every earlier triangle exactly where it was."""
    rng = np.random.default_rng(8)
    s = ppm_core.Scene()
    s.geometry_layout = layout
    m = s.add_material("grey")
    n = 100_000  # (the BVH's arrays come in 2 MB pages: fewer triangles would measure the rounding)
    corners = rng.uniform(-1, 1, size=(n, 1, 3)) + rng.normal(scale=0.01, size=(n, 3, 3))
    s.add_mesh("soup", corners.reshape(-1, 3), np.arange(3 * n).reshape(n, 3), materials=m, object_id=1)
    o = rng.normal(size=(5000, 3))
    o *= 3.0 / np.linalg.norm(o, axis=1)[:, None]
    d = rng.uniform(-1, 1, size=o.shape) - o
    before = s.intersect(o, d)
    s.set_camera(np.eye(4), 4, 3)
    bytes_per_triangle = ppm_core.Renderer(s, photons_per_pass=10).stats()["memory"]["scene"] / n
    # A soup whose triangles share no vertex: vertices 72, leaf record 20, BVH nodes about 22, triangle
    # info 8, slot 4 (127 measured compact; 239 once, with the leaf's copy of the corners and a copy in
    # triangle order kept), and the corners' copy with the record again (96) where copied.
    assert bytes_per_triangle < (135 if layout == "compact" else 231)

    far = np.array([[10.0, 10.0, 10.0], [11.0, 10.0, 10.0], [10.0, 11.0, 10.0]])
    s.add_mesh("far", far, np.array([[0, 1, 2]]), materials=m, object_id=2)
    after = s.intersect(np.vstack([o, [[10.2, 10.2, 12.0]]]), np.vstack([d, [[0.0, 0.0, -1.0]]]))
    for key in ("t", "normal", "primitive", "object"):
        np.testing.assert_array_equal(after[key][:-1], before[key])
    assert after["primitive"][-1] == n and after["object"][-1] == 2 and after["t"][-1] == 2.0

def test_a_ray_cast_alone_gets_the_batch_answer():
    """On a mesh too large for the caches the batch interleaves several rays' BVH
    walks (777 rays: not a whole number of the binding's batches of 256)."""
    rng = np.random.default_rng(6)
    n = 50_000
    corners = rng.uniform(-1, 1, size=(n, 1, 3)) + rng.normal(scale=0.01, size=(n, 3, 3))
    s = ppm_core.Scene()
    s.add_material("grey")
    s.add_mesh("soup", corners.reshape(-1, 3), np.arange(3 * n).reshape(n, 3))
    o = rng.normal(size=(777, 3))
    d = rng.uniform(-0.5, 0.5, size=o.shape) - o
    batch = s.intersect(o, d, threads=1)
    assert 0.2 < np.isfinite(batch["t"]).mean() < 0.95
    for i in range(len(o)):
        alone = s.intersect(o[i : i + 1], d[i : i + 1], threads=1)
        for key in ("t", "normal", "primitive", "object"):
            np.testing.assert_array_equal(alone[key][0], batch[key][i])


def test_camera_rays_are_the_renderers_through_pixel_centres():
    """Scene.camera_rays (the add-on's Depth and Normal passes) gives the camera's own rays: from the
    eye plus clip start, through each pixel centre, bottom row first."""
    scene = ppm_core.Scene()
    camera = np.eye(4)
    camera[:3, 3] = (1.0, 2.0, 3.0)  # looks down -Z
    scene.set_camera(camera, 4, 2, fov=np.radians(90), clip_start=0.5, shift_x=0.0)
    origins, directions = scene.camera_rays()
    assert origins.shape == directions.shape == (8, 3)
    np.testing.assert_allclose(np.linalg.norm(directions, axis=1), 1.0)
    # Pixel (x, y) centre at image-plane ((x + 0.5 - 2) / 2, (y + 0.5 - 1) / 2) at unit distance (fov 90 deg).
    for index, (x, y) in enumerate([(x, y) for y in range(2) for x in range(4)]):
        expected = np.array([(x + 0.5 - 2) / 2, (y + 0.5 - 1) / 2, -1.0])
        expected /= np.linalg.norm(expected)
        np.testing.assert_allclose(directions[index], expected, atol=1e-12)
        # Clip start is measured along the view axis: the origin lies on the plane z = 3 - 0.5.
        np.testing.assert_allclose(origins[index][2], 2.5, atol=1e-12)
    with pytest.raises(ValueError, match="no camera"):
        ppm_core.Scene().camera_rays()
