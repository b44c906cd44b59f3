"""Blender's axes and units to Bouguer's. Blender is z-up; Bouguer scenes are y-up (docs/scene-format.md).
The conversion is glTF's, as Blender's glTF exporter writes it: x_b = x, y_b = z, z_b = -y (a rotation
of -90 degrees about x, so handedness and windings are kept). Lengths are Blender units times the
scene's unit scale (1 BU = scale_length metres)."""
import numpy as np

# Bouguer coordinates of a Blender vector: rows are Bouguer's x, y, z.
TO_BOUGUER = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])


def unit_scale(scene):
    """Metres per Blender unit."""
    s = scene.unit_settings
    return s.scale_length if s.system != "NONE" else 1.0


def point(v, metres_per_unit):
    return (TO_BOUGUER @ np.asarray(v, dtype=float) * metres_per_unit).tolist()


def direction(v):
    d = TO_BOUGUER @ np.asarray(v, dtype=float)
    return (d / np.linalg.norm(d)).tolist()


def matrix(world, metres_per_unit):
    """A Blender world matrix (mathutils.Matrix) as Bouguer's row-major 4x4 transform step: object
    coordinates in Blender units to Bouguer's world in metres."""
    m = np.array([list(row) for row in world], dtype=float)
    c = np.eye(4)
    c[:3, :3] = TO_BOUGUER * metres_per_unit
    out = c @ m
    out[3] = [0.0, 0.0, 0.0, 1.0]
    return out.tolist()
