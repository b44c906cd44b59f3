"""The evaluated depsgraph as a Bouguer scene description: the dict bouguer.load_dict reads (the JSON
schema of docs/scene-format.md) and the meshes it names, so every value goes through the builder's
checks as every front end's does. Plain functions of the depsgraph: no UI, no render engine."""

from . import axes, camera, lights, materials, meshes, world
from .report import Reports

GEOMETRY = {"MESH", "CURVE", "SURFACE", "META", "FONT"}


class Export:
    def __init__(self):
        self.scene = {}
        self.meshes = {}
        self.parts = {}  # object key -> {material index: mesh arrays}
        self.reports = Reports()


def pbr_supported(bouguer):
    """Whether this module's loader knows the `pbr` role (the coordinator adds it beside the glTF reader)."""
    probe = {"objects": [{"shape": {"type": "quad", "size": [1, 1]}, "pbr": {"base_color": [0.5, 0.5, 0.5]}}]}
    try:
        bouguer.load_dict(probe)
        return True
    except bouguer.Error:
        return False


def render_settings(settings):
    if settings is None:
        return {"integrator": "path", "spectral": "hero"}
    return {"integrator": settings.integrator, "spectral": settings.spectral, "max_depth": settings.max_depth,
            "seed": settings.seed, "spp": settings.spp}


def export_scene(depsgraph, bouguer, settings=None):
    """The scene as an Export: .scene (the dict), .meshes (for load_dict), .reports.warnings."""
    scene = depsgraph.scene
    out = Export()
    out.spectral = settings.spectral if settings is not None else "hero"
    out.attenuation = bouguer.attenuation_spectrum
    per_unit = axes.unit_scale(scene)
    cam = scene.camera.evaluated_get(depsgraph) if scene.camera else None
    objects, point_lights, media = [], [], {}
    translated = {}  # material name -> Translation
    pbr = pbr_supported(bouguer)
    for inst in depsgraph.object_instances:
        obj = inst.object
        if obj.type == "LIGHT":
            lights.export(obj, inst.matrix_world, per_unit, out.reports, objects, point_lights)
        elif obj.type in GEOMETRY:
            add_geometry(out, inst, obj, per_unit, translated, media, objects, pbr)
    s = {"camera": camera.export(scene, cam, per_unit, out.reports), "render": render_settings(settings),
         "world_medium": "vacuum", "objects": objects}
    if media:
        s["media"] = media
    if point_lights:
        s["lights"] = point_lights
    background = world.export(scene, out.reports)
    if background is not None:
        s["background"] = background
    out.scene = s
    return out


def mesh_parts(obj):
    mesh = obj.to_mesh()  # the evaluated object's mesh: modifiers and geometry nodes applied
    try:
        return meshes.split_by_material(mesh) if mesh is not None else {}
    finally:
        obj.to_mesh_clear()


def add_geometry(out, inst, obj, per_unit, translated, media, objects, pbr):
    # Instances of one object share its arrays; each instance is an object with its own matrix.
    key = obj.name if not inst.is_instance else f"{obj.name}@{obj.data.name if obj.data else ''}"
    if key not in out.parts:
        out.parts[key] = mesh_parts(obj)
        for index, part in out.parts[key].items():
            out.meshes[f"{key}#{index}"] = part
    slots = obj.material_slots
    matrix = axes.matrix(inst.matrix_world, per_unit)
    for index, part in out.parts[key].items():
        material = slots[index].material if index < len(slots) else None
        t = translation(material, out.reports, per_unit, translated, pbr, out.spectral, out.attenuation)
        media.update(t.media)
        roles = dict(t.roles)
        if "uvs" not in part and uses_texture(roles):
            out.reports.warn(f"Object '{obj.name}': an image texture needs a UV map; rendered with a constant colour")
            roles = without_texture(roles)
        name = obj.name if index == 0 else f"{obj.name} ({index})"
        objects.append(dict({"name": name, "shape": {"type": "mesh", "arrays": f"{key}#{index}"},
                             "transform": [{"matrix": matrix}]}, **roles))


def translation(material, reports, per_unit, translated, pbr, spectral, attenuation):
    key = material.name if material is not None else None
    if key not in translated:
        translated[key] = materials.translate(material, reports, 1.0 / per_unit, pbr, spectral, attenuation)
    return translated[key]


def uses_texture(roles):
    return "texture" in repr(roles)


def without_texture(roles):
    roles = dict(roles)
    if "material" in roles and isinstance(roles["material"].get("reflectance"), dict) and \
            "texture" in roles["material"]["reflectance"]:
        roles["material"] = {"type": "diffuse", "reflectance": {"rgb": [materials.DEFAULT_GREY] * 3}}
    if "pbr" in roles:
        roles["pbr"] = {k: v for k, v in roles["pbr"].items() if k != "base_color_texture"}
    return roles
