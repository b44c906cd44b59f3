"""The world: Background's colour x strength as a uniform radiance, or an Environment Texture's
equirectangular OpenEXR as Bouguer's environment map."""
import os

import bpy

from . import nodes

# Blender's equirectangular image has its centre looking along Blender's +x, columns running towards
# -y; Bouguer's along -z, columns towards +x (docs/scene-format.md). In Bouguer's axes Blender's +x is
# +x and -y is +z: a quarter turn about +y, which is Bouguer's rotate_deg of +90 (checked against
# Cycles in tests/blender/test_lights.py: -90, 0 and 180 differ by 0.26 or more, 90 by 0.005).
ENVIRONMENT_ROTATE_DEG = 90.0


def export(scene, reports):
    world = scene.world
    if world is None:
        return None
    owner = f"World '{world.name}'"
    if not world.use_nodes:
        return {"spectrum": {"rgb": [max(0.0, c) for c in world.color]}, "scale": 1.0}
    out = nodes.active_output(world.node_tree, "OUTPUT_WORLD")
    node = nodes.linked_node(out.inputs["Surface"]) if out else None
    if node is None:
        return None
    if node.type != "BACKGROUND":
        reports.warn(f"{owner}: node '{node.name}' ({node.bl_label}) is not translated; the world is black")
        return None
    strength = nodes.constant(node.inputs["Strength"], owner, reports)
    colour_socket = node.inputs["Color"]
    texture = nodes.linked_node(colour_socket)
    if texture is not None and texture.type == "TEX_ENVIRONMENT":
        env = environment(texture, strength, owner, reports)
        if env is not None:
            return env
        colour = average_colour(texture.image) if texture.image else [0.0, 0.0, 0.0]
    else:
        colour = nodes.constant(colour_socket, owner, reports, "colour")
    return {"spectrum": {"rgb": [max(0.0, c) for c in colour]}, "scale": strength}


def environment(texture, strength, owner, reports):
    image = texture.image
    if image is None:
        return None
    if texture.projection != "EQUIRECTANGULAR":
        reports.warn(f"{owner}: the environment's {texture.projection.lower()} projection is not translated; "
                     "rendered with the image's average colour")
        return None
    if texture.inputs["Vector"].is_linked:
        reports.warn(f"{owner}: the environment's vector input (a mapping) is not translated")
    path = bpy.path.abspath(image.filepath, library=image.library)
    if image.packed_file is not None or os.path.splitext(path)[1].lower() not in (".exr", ".pfm"):
        reports.warn(f"{owner}: environment image '{image.name}' is not an OpenEXR file on disk (Bouguer reads "
                     "EXR and PFM maps); rendered with its average colour")
        return None
    return {"environment": os.path.abspath(path), "scale": strength, "rotate_deg": ENVIRONMENT_ROTATE_DEG}


def average_colour(image):
    import numpy as np
    px = np.empty(len(image.pixels), dtype=np.float32)
    image.pixels.foreach_get(px)
    return px.reshape(-1, image.channels)[:, :3].mean(axis=0).tolist() if px.size else [0.0, 0.0, 0.0]
