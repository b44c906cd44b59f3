"""Evaluated meshes (modifiers applied) as arrays for bouguer.load_dict(meshes=...): one mesh per
material slot, a vertex per face corner that Blender's loops give (split normals: flat faces get
their face normal, smooth ones the interpolated normal, auto smooth its creases), and the active UV
map. Coordinates stay in the object's own frame; the object's transform carries it into the world."""
import numpy as np


def corner_arrays(mesh):
    """Per triangle corner loop indices and material indices, and the per-loop attributes."""
    mesh.calc_loop_triangles()
    if hasattr(mesh, "calc_normals_split"):  # Blender < 4.1; later versions keep them up to date
        mesh.calc_normals_split()
    n_tri = len(mesh.loop_triangles)
    loops = np.empty(n_tri * 3, dtype=np.int64)
    mesh.loop_triangles.foreach_get("loops", loops)
    materials = np.empty(n_tri, dtype=np.int64)
    mesh.loop_triangles.foreach_get("material_index", materials)
    n_loops = len(mesh.loops)
    vertex = np.empty(n_loops, dtype=np.int64)
    mesh.loops.foreach_get("vertex_index", vertex)
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    normals = np.empty(n_loops * 3, dtype=np.float32)
    mesh.loops.foreach_get("normal", normals)
    uv_layer = mesh.uv_layers.active
    uvs = None
    if uv_layer is not None:
        uvs = np.empty(n_loops * 2, dtype=np.float32)
        uv_layer.data.foreach_get("uv", uvs)
        uvs = uvs.reshape(-1, 2).astype(np.float64)
    return (loops.reshape(-1, 3), materials, co.reshape(-1, 3).astype(np.float64)[vertex],
            normals.reshape(-1, 3).astype(np.float64), uvs)


def split_by_material(mesh):
    """{material index: {"positions", "triangles", "normals"[, "uvs"]}} for the material indices used."""
    loops, materials, positions, normals, uvs = corner_arrays(mesh)
    parts = {}
    for index in np.unique(materials):
        corners = loops[materials == index]
        used, triangles = np.unique(corners.ravel(), return_inverse=True)
        n = normals[used]
        length = np.linalg.norm(n, axis=1)
        # A degenerate face's corner has no normal: give it none rather than refuse the mesh.
        part = {"positions": positions[used], "triangles": triangles.reshape(-1, 3)}
        if np.all(length > 0) and np.all(np.isfinite(n)):
            part["normals"] = n
        if uvs is not None:
            part["uvs"] = uvs[used]
        parts[int(index)] = part
    return parts
