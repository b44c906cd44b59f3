"""The scene camera: perspective and orthographic, sensor fit, shift (docs/blender.md, "Camera")."""
import math

from mathutils import Vector

from . import axes


def resolution(scene):
    r = scene.render
    f = r.resolution_percentage / 100.0
    return max(1, int(r.resolution_x * f)), max(1, int(r.resolution_y * f))


def fitted(cam, width, height):
    """Blender's sensor fit: which image side the sensor (or ortho_scale) spans, in pixels, and the
    sensor's size in mm (Blender's BKE_camera_sensor_fit: AUTO takes the larger side)."""
    fit = cam.sensor_fit
    if fit == "AUTO":
        return max(width, height), cam.sensor_width
    if fit == "HORIZONTAL":
        return width, cam.sensor_width
    return height, cam.sensor_height


def export(scene, camera_object, metres_per_unit, reports):
    width, height = resolution(scene)
    if scene.render.pixel_aspect_x != scene.render.pixel_aspect_y:
        reports.warn("Camera: non-square pixels are not translated (rendered square)")
    c = {"resolution": [width, height]}
    if camera_object is None:
        reports.warn("Scene: no camera; rendered from Bouguer's default camera")
        return c
    cam = camera_object.data
    fit_px, sensor_mm = fitted(cam, width, height)
    shorter = min(width, height)
    m = camera_object.matrix_world
    rot = m.to_3x3().normalized()
    position = m.translation
    forward = rot @ Vector((0.0, 0.0, -1.0))
    up = rot @ Vector((0.0, 1.0, 0.0))
    c["position"] = axes.point(position, metres_per_unit)
    c["look_at"] = axes.point(position + forward, metres_per_unit)
    c["up"] = axes.direction(up)
    if cam.type == "ORTHO":
        c["type"] = "orthographic"
        c["width"] = cam.ortho_scale * shorter / fit_px * metres_per_unit
    else:
        if cam.type != "PERSP":
            reports.warn(f"Camera '{camera_object.name}': {cam.type.lower()} cameras are not translated (rendered as perspective)")
        c["type"] = "pinhole"
        half_short = sensor_mm / (2.0 * cam.lens) * shorter / fit_px
        c["fov_deg"] = math.degrees(2.0 * math.atan(half_short))
    # Blender's shift is in units of the fitted side; Bouguer's in units of the shorter side.
    if cam.shift_x or cam.shift_y:
        c["shift"] = [cam.shift_x * fit_px / shorter, cam.shift_y * fit_px / shorter]
    return c
