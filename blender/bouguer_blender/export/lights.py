"""Blender's lights in Blender's watts, converted as Cycles 3.4 converts them, so that a diffuse plane
under each gives Cycles' pixel values (tests/blender/test_lights.py measures it):
- point and spot of power P: radiant intensity P/(4 pi) per steradian (RGB units: colour x that); a
  point with a radius r: an emitting sphere of radius r and that intensity, radiance P/(4 pi)/(pi r^2);
- sun of strength S: irradiance S on a surface facing it;
- area of power P and area A: radiance P/(4 A) (Cycles' 1/4, not 1/pi);
- the world's colour x strength: radiance.
Cycles works in Blender units, so with a unit scale s (metres per unit) intensities are multiplied by
s^2: the irradiance at a distance of d units is then the same number as in Cycles."""
import math

from mathutils import Vector

from . import axes

# Larger suns are soft: Bouguer's distant light is a delta, so say so beyond this.
SUN_ANGLE_WARN_RAD = math.radians(2.0)


def spectrum(colour, scale):
    return {"spectrum": {"rgb": [max(0.0, float(c)) for c in colour[:3]]}, "scale": float(scale)}


def spot_falloff_deg(spot_size, spot_blend):
    """Cycles' spot: the cone's half-angle a, a smoothstep over cos from cos(a) to cos(a) + (1 - cos(a)) * blend;
    Bouguer's falloff begins at the angle of the latter."""
    cos_half = math.cos(spot_size / 2.0)
    return math.degrees(math.acos(min(1.0, cos_half + (1.0 - cos_half) * spot_blend)))


def area_shape(light):
    """The emitter's shape in the light's local frame and its area in Blender units squared."""
    sx = light.size
    sy = light.size_y if light.shape in ("RECTANGLE", "ELLIPSE") else light.size
    if light.shape in ("SQUARE", "RECTANGLE"):
        return {"type": "quad", "size": [sx, sy]}, [1.0, 1.0], sx * sy
    # A disk of radius 1/2 scaled to the ellipse's axes.
    return {"type": "disk", "radius": 0.5, "segments": 64}, [sx, sy], math.pi * sx * sy / 4.0


def export(obj, matrix_world, metres_per_unit, reports, objects, lights):
    """Appends the light's Bouguer light (point, spot, distant) or emitting object (area; a point with
    a radius, an emitting sphere) to `lights` or `objects`."""
    light = obj.data
    name = obj.name
    colour = light.color
    if light.use_nodes:
        reports.warn(f"Light '{name}': its node tree is not translated (its colour and power are)")
    rot = matrix_world.to_3x3().normalized()
    position = matrix_world.translation
    down = rot @ Vector((0.0, 0.0, -1.0))
    s2 = metres_per_unit ** 2
    if light.type in ("POINT", "SPOT"):
        intensity = light.energy / (4.0 * math.pi) * s2
        radius = light.shadow_soft_size
        if light.type == "POINT" and radius > 0.0:
            # Cycles 3.4's point light with a radius is a disk of that radius facing the point it lights,
            # radiance P/(4 pi)/(pi r^2) (intensity P/(4 pi), its soft shadows and its highlight). An
            # emitting sphere of that radius and radiance looks the same from everywhere: the same
            # disk, the same intensity, and Bouguer samples it by the cone it subtends (an exact
            # spherical lamp: one-sided, untextured, translated only). The radius ignores the object's
            # scale, as Cycles' does. In Blender units the radiance is P/(4 pi^2 r^2) for any unit scale.
            radius_m = radius * metres_per_unit
            objects.append(dict({"name": name, "shape": {"type": "sphere", "radius": radius_m},
                                 "transform": [{"translate": axes.point(position, metres_per_unit)}]},
                                emission=spectrum(colour, intensity / (math.pi * radius_m ** 2))))
            return
        l = dict({"type": light.type.lower(), "position": axes.point(position, metres_per_unit)},
                 **spectrum(colour, intensity))
        if light.type == "SPOT":
            l["direction"] = axes.direction(down)
            l["cone_deg"] = math.degrees(light.spot_size / 2.0)
            l["falloff_deg"] = spot_falloff_deg(light.spot_size, light.spot_blend)
            if radius > 0.0:
                l["radius"] = radius * metres_per_unit
        lights.append(l)
    elif light.type == "SUN":
        if light.angle > SUN_ANGLE_WARN_RAD:
            reports.warn(f"Light '{name}': the sun's angle of {math.degrees(light.angle):.1f} degrees is not "
                         "translated (Bouguer's distant light is sharp)")
        lights.append(dict({"type": "distant", "direction": axes.direction(down)},
                           **spectrum(colour, light.energy)))  # a sun's energy is its strength, W/m^2
    elif light.type == "AREA":
        if getattr(light, "spread", math.pi) < math.pi - 1e-6:
            reports.warn(f"Light '{name}': the area light's spread is not translated (it spreads 180 degrees)")
        shape, scale_xy, area = area_shape(light)
        # Blender's area light emits along its local -z; Bouguer's flat shapes face +z.
        steps = [{"rotate_deg": [180.0, [1.0, 0.0, 0.0]]}]
        if scale_xy != [1.0, 1.0]:
            steps.insert(0, {"scale": [scale_xy[0], scale_xy[1], 1.0]})
        steps.append({"matrix": axes.matrix(matrix_world, metres_per_unit)})
        # The object's scale scales the light (Cycles takes its axes from the object's matrix).
        area *= matrix_world.col[0].xyz.length * matrix_world.col[1].xyz.length
        if not area > 0.0:
            reports.warn(f"Light '{name}': an area light of size 0 emits nothing; left out")
            return
        objects.append(dict({"name": name, "shape": shape, "transform": steps},
                            emission=spectrum(colour, light.energy / (4.0 * area))))
    else:
        reports.warn(f"Light '{name}': {light.type.lower()} lights are not translated")
