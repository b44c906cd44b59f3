"""Blender materials as Bouguer roles (docs/blender.md, "Materials"): an opaque `material`, an
`emission`, a `pbr` surface (the glTF reader's mapping of a metallic-roughness material), or a
dielectric interface `inside` a medium. Volumes are Cycles' own units: Volume Absorption gives
sigma_a = density (1 - colour), Volume Scatter sigma_s = density colour, per Blender unit, here per
metre. The three channel values are lifted to a spectrum by the glTF reader's own lift of an
attenuation colour (bouguer.attenuation_spectrum, docs/assets.md): the transmittance over a
reference length is the smooth reflectance lift of its colour, tabulated at 1 nm, made exact at the
rgb3 lines (700.0, 546.1, 435.8 nm), so that `rgb3` reproduces Cycles' per-channel transmittance."""
import math
import os

import bpy

from . import nodes
from ..properties import SELLMEIER

RGB3_NM = [435.8, 546.1, 700.0]  # blue, green, red: increasing
DEFAULT_GREY = 0.8                 # Cycles' surface without a material


def channel_table(rgb, attenuation):
    """sigma (per metre, three channels) as a 1 nm table: over the reference length d = 1/max(sigma)
    the transmittance exp(-sigma d) lies in [1/e, 1], where the reflectance lift is smooth;
    `attenuation` is bouguer.attenuation_spectrum, the glTF reader's lift of that colour over d."""
    d = 1.0 / max(rgb)
    nm, sigma = attenuation([math.exp(-x * d) for x in rgb], d)
    return {"unit": "attenuation_per_m", "wavelength_nm": nm.tolist(), "value": sigma.tolist()}


def clamp01(rgb):
    return [min(1.0, max(0.0, float(c))) for c in rgb[:3]]


class Translation:
    """One material's roles for an object, and the media they name."""

    def __init__(self):
        self.roles = {}
        self.media = {}
        self.spectral = "hero"


def texture_of(socket, owner, reports):
    """An Image Texture feeding a colour input, as Bouguer's {"texture": path}, or None."""
    node = nodes.linked_node(socket)
    if node is None or node.type != "TEX_IMAGE" or node.image is None:
        return None
    image = node.image
    path = bpy.path.abspath(image.filepath, library=image.library)
    if image.packed_file is not None or not os.path.isfile(path):
        reports.warn(f"{owner}: image '{image.name}' is not a file on disk (packed or generated); rendered with "
                     f"the input's own colour")
        return None
    if node.inputs["Vector"].is_linked:
        reports.warn(f"{owner}: the mapping of image '{image.name}' is not translated (the active UV map is used)")
    return {"texture": os.path.abspath(path)}


def reflectance(rgb, spectral):
    """An RGB reflectance: lifted to a smooth spectrum (its colour under D65 is the RGB), except in
    `rgb3`, which reads reflectances at its three lines (docs/rendering.md): there the three values
    themselves, so that rgb3 multiplies colours as Cycles' RGB does."""
    rgb = clamp01(rgb)
    if spectral == "rgb3":
        return {"wavelength_nm": RGB3_NM, "value": [rgb[2], rgb[1], rgb[0]]}
    return {"rgb": rgb}


def colour_or_texture(socket, owner, reports, spectral):
    tex = texture_of(socket, owner, reports)
    if tex is not None:
        return tex
    return reflectance(nodes.constant(socket, owner, reports, "colour"), spectral)


def surface_closure(node, owner, reports):
    """Folds Mix and Add shaders whose factor is a constant 0 or 1; otherwise the stronger input,
    with a report."""
    while node is not None and node.type in ("MIX_SHADER", "ADD_SHADER"):
        if node.type == "MIX_SHADER":
            fac = nodes.constant(node.inputs[0], owner, reports)
            a, b = nodes.linked_node(node.inputs[1]), nodes.linked_node(node.inputs[2])
            if fac not in (0.0, 1.0):
                reports.warn(f"{owner}: Mix Shader '{node.name}' with factor {fac:.3g} is not translated; rendered "
                             f"with its {'second' if fac >= 0.5 else 'first'} shader")
            node = b if fac >= 0.5 else a
        else:
            a, b = nodes.linked_node(node.inputs[0]), nodes.linked_node(node.inputs[1])
            if a is not None and b is not None:
                reports.warn(f"{owner}: Add Shader '{node.name}' is not translated; rendered with its first shader")
            node = a if a is not None else b
    return node


def volume_coefficients(node, owner, reports, per_m):
    """(sigma_a RGB, sigma_s RGB, g) per metre of a volume node tree (Add Shader sums), or None."""
    if node is None:
        return None
    if node.type == "ADD_SHADER":
        parts = [volume_coefficients(nodes.linked_node(s), owner, reports, per_m) for s in node.inputs[:2]]
        parts = [p for p in parts if p is not None]
        if not parts:
            return None
        sa = [sum(p[0][i] for p in parts) for i in range(3)]
        ss = [sum(p[1][i] for p in parts) for i in range(3)]
        return sa, ss, max((p[2] for p in parts), key=abs)
    zero = [0.0, 0.0, 0.0]
    if node.type == "VOLUME_ABSORPTION":
        c = clamp01(nodes.constant(node.inputs["Color"], owner, reports, "colour"))
        d = max(0.0, nodes.constant(node.inputs["Density"], owner, reports))
        return [d * (1.0 - x) * per_m for x in c], zero, 0.0
    if node.type == "VOLUME_SCATTER":
        c = clamp01(nodes.constant(node.inputs["Color"], owner, reports, "colour"))
        d = max(0.0, nodes.constant(node.inputs["Density"], owner, reports))
        return zero, [d * x * per_m for x in c], nodes.constant(node.inputs["Anisotropy"], owner, reports)
    if node.type == "PRINCIPLED_VOLUME":
        # Cycles' svm_node_principled_volume: sigma_s = density colour, and
        # sigma_a = density max(1 - colour, 0) max(1 - sqrt(absorption colour), 0).
        c = clamp01(nodes.constant(node.inputs["Color"], owner, reports, "colour"))
        d = max(0.0, nodes.constant(node.inputs["Density"], owner, reports))
        a = clamp01(nodes.constant(node.inputs["Absorption Color"], owner, reports, "colour"))
        g = nodes.constant(node.inputs["Anisotropy"], owner, reports)
        for name in ("Emission Strength", "Blackbody Intensity"):
            s = node.inputs.get(name)
            if s is not None and (s.is_linked or s.default_value > 0):
                reports.warn(f"{owner}: the Principled Volume's {name.lower()} is not translated")
        return ([d * (1.0 - x) * max(0.0, 1.0 - y ** 0.5) * per_m for x, y in zip(c, a)],
                [d * x * per_m for x in c], g)
    reports.warn(f"{owner}: volume node '{node.name}' ({node.bl_label}) is not translated; no volume")
    return None


# The indices Bouguer models (media/ior.h); Blender allows 0 to 1000.
MIN_IOR, MAX_IOR = 1.0, 4.99


def checked_ior(ior, owner, reports):
    """An IOR within what Bouguer models, clamped with a report (an IOR below 1, Cycles' trick for an
    air bubble in a liquid, is an object of air inside the liquid with a priority here)."""
    clamped = min(MAX_IOR, max(MIN_IOR, ior))
    if clamped != ior:
        reports.warn(f"{owner}: IOR {ior:.4g} is rendered as {clamped:.4g} (Bouguer models 1 to 5; an air bubble "
                     "in a liquid is an object of air inside it with a priority, docs/blender.md)")
    return clamped


def medium_of(ior, volume, attenuation):
    m = {"ior": ior}
    if volume is None:
        return m
    sa, ss, g = volume
    if any(v > 0 for v in sa):
        m["absorption"] = channel_table(sa, attenuation)
    if any(v > 0 for v in ss):
        m["scattering"] = dict(channel_table(ss, attenuation), phase={"type": "henyey_greenstein", "g": max(-0.99, min(0.99, g))}
                               if abs(g) > 1e-6 else {"type": "isotropic"})
    return m


def library_medium(settings):
    """A medium of Bouguer's library or a material file, from material.bouguer."""
    if settings.source == "LIBRARY":
        m = {"absorption": {"library": settings.library, "concentration": settings.concentration}}
    else:
        m = {"absorption": {"csv": os.path.abspath(bpy.path.abspath(settings.file)),
                            "concentration": settings.concentration}}
    if settings.ior_source == "NUMBER":
        m["ior"] = settings.ior
    elif settings.ior_source == "ABBE":
        m["ior"] = {"abbe": {"n_d": settings.ior, "V_d": settings.abbe}}
    elif settings.ior_source == "SELLMEIER":
        m["ior"] = {"library": settings.sellmeier if settings.sellmeier in SELLMEIER else "N-BK7"}
    return m  # "Medium's Own": the library entry's index, or the file's '# ior:' (the builder asks for one)


def interface(t, name, medium, roughness, settings, owner=None, reports=None):
    t.media[name] = medium
    t.roles["inside"] = name
    if roughness > 0.0:
        t.roles["roughness"] = min(1.0, roughness)
    if settings is not None and settings.use_priority:
        if roughness > 0.0 and reports is not None:  # nested media take smooth interfaces only
            reports.warn(f"{owner}: a rough glass takes no priority (nested media need smooth interfaces); "
                         "rendered without it")
        else:
            t.roles["priority"] = settings.priority


def translate(material, reports, per_m, pbr_supported, spectral, attenuation):
    """The roles of a Blender material (None: Cycles' default grey) and the media they name; `attenuation`
    is bouguer.attenuation_spectrum."""
    t = Translation()
    t.spectral, t.attenuation = spectral, attenuation
    if material is None:
        t.roles["material"] = {"type": "diffuse", "reflectance": reflectance([DEFAULT_GREY] * 3, spectral)}
        return t
    owner = f"Material '{material.name}'"
    settings = getattr(material, "bouguer", None)
    medium_name = material.name
    if settings is not None and settings.source in ("LIBRARY", "FILE"):
        interface(t, medium_name, library_medium(settings), 0.0, settings)
        return t
    if not material.use_nodes:
        t.roles["material"] = {"type": "diffuse", "reflectance": reflectance(material.diffuse_color, spectral)}
        return t
    out = nodes.active_output(material.node_tree, "OUTPUT_MATERIAL")
    if out is None:
        reports.warn(f"{owner}: no Material Output node; rendered grey")
        t.roles["material"] = {"type": "diffuse", "reflectance": reflectance([DEFAULT_GREY] * 3, spectral)}
        return t
    volume = volume_coefficients(nodes.linked_node(out.inputs["Volume"]), owner, reports, per_m)
    node = surface_closure(nodes.linked_node(out.inputs["Surface"]), owner, reports)
    surface(t, node, owner, reports, volume, medium_name, settings, pbr_supported)
    return t


def surface(t, node, owner, reports, volume, medium_name, settings, pbr_supported):
    if node is None:
        if volume is not None:  # a volume without a surface: index-matched, as Cycles renders it
            interface(t, medium_name, medium_of(1.0, volume, t.attenuation), 0.0, settings)
        else:
            reports.warn(f"{owner}: nothing is connected to the surface; rendered black")
            t.roles["material"] = {"type": "diffuse", "reflectance": 0.0}
        return
    kind = node.type
    if kind == "BSDF_DIFFUSE":
        if nodes.constant(node.inputs["Roughness"], owner, reports) > 0.0:
            reports.warn(f"{owner}: the Diffuse BSDF's roughness (Oren-Nayar) is not translated (Lambertian)")
        t.roles["material"] = {"type": "diffuse", "reflectance": colour_or_texture(node.inputs["Color"], owner, reports, t.spectral)}
    elif kind == "EMISSION":
        c = nodes.constant(node.inputs["Color"], owner, reports, "colour")
        s = nodes.constant(node.inputs["Strength"], owner, reports)
        t.roles["emission"] = {"spectrum": {"rgb": [max(0.0, x) for x in c]}, "scale": max(0.0, s), "two_sided": True}
    elif kind == "BSDF_GLASS":
        glass_tint(node.inputs["Color"], owner, reports)
        ior = nodes.constant(node.inputs["IOR"], owner, reports)
        r = nodes.constant(node.inputs["Roughness"], owner, reports)
        interface(t, medium_name, medium_of(checked_ior(ior, owner, reports), volume, t.attenuation), r * r,  # GGX alpha = r^2
                  settings, owner, reports)
    elif kind == "BSDF_PRINCIPLED":
        principled(t, node, owner, reports, volume, medium_name, settings, pbr_supported)
    else:
        colour = node.inputs.get("Color") or node.inputs.get("Base Color")
        rgb = clamp01(nodes.constant(colour, owner, reports, "colour")) if colour is not None else [DEFAULT_GREY] * 3
        reports.warn(f"{owner}: node '{node.name}' ({node.bl_label}) is not translated; rendered diffuse with its colour")
        t.roles["material"] = {"type": "diffuse", "reflectance": reflectance(rgb, t.spectral)}
    if volume is not None and "inside" not in t.roles:
        reports.warn(f"{owner}: a volume needs a transmitting surface (Glass, Principled with transmission, or "
                     "none); the volume is not rendered")


def glass_tint(socket, owner, reports):
    c = nodes.constant(socket, owner, reports, "colour")
    if min(c) < 0.999:
        reports.warn(f"{owner}: a coloured glass surface (Cycles tints each pass through the surface) is not "
                     "translated; colour glass by a Volume Absorption or a library medium (docs/blender.md)")


def principled(t, node, owner, reports, volume, medium_name, settings, pbr_supported):
    get = lambda *names: nodes.find_input(node, *names)
    base = get("Base Color")
    metallic = nodes.constant(get("Metallic"), owner, reports)
    roughness = nodes.constant(get("Roughness"), owner, reports)
    transmission = nodes.constant(get("Transmission", "Transmission Weight"), owner, reports)
    ior = nodes.constant(get("IOR"), owner, reports)
    emission = nodes.constant(get("Emission", "Emission Color"), owner, reports, "colour")
    strength_socket = get("Emission Strength")
    strength = nodes.constant(strength_socket, owner, reports) if strength_socket is not None else 1.0
    emits = strength > 0.0 and max(emission) > 0.0
    if transmission >= 0.5 and metallic < 0.5 and not emits:
        # A dielectric interface, as the Glass BSDF: physics, not Cycles' blend of lobes (docs/blender.md).
        if transmission < 1.0:
            reports.warn(f"{owner}: transmission {transmission:.3g} is rendered as 1 (a dielectric interface)")
        glass_tint(base, owner, reports)
        interface(t, medium_name, medium_of(checked_ior(ior, owner, reports), volume, t.attenuation), roughness * roughness,
                  settings, owner, reports)
        return
    if transmission > 0.0:  # below 0.5, under a metal (Cycles weights it by 1 - metallic) or emitting
        reports.warn(f"{owner}: transmission {transmission:.3g} is not rendered (an object is a dielectric from "
                     "transmission 0.5 up, when it is not metallic and does not emit)")
    if pbr_supported:
        # Opaque: the glass case is above, so the pbr role never transmits here (its ior is unused).
        p = {"metallic": min(1.0, max(0.0, metallic)), "roughness": min(1.0, max(0.0, roughness)),
             "transmission": 0.0}
        tex = texture_of(base, owner, reports)
        if tex is not None:
            p["base_color_texture"] = tex
        p["base_color"] = clamp01(nodes.constant(base, owner, reports, "colour")) if tex is None else [1.0, 1.0, 1.0]
        if emits:
            p["emission"] = [max(0.0, x) for x in emission]
            p["emission_strength"] = strength
        t.roles["pbr"] = p
        return
    # The pbr role is not in this module yet: the glTF reader's untextured rules, said once.
    reports.warn(f"{owner}: this bouguer module has no 'pbr' role; the Principled BSDF is rendered as "
                 "its base colour as a diffuse reflectance (or its emission where it emits)")
    if emits:
        t.roles["emission"] = {"spectrum": {"rgb": [max(0.0, x) for x in emission]}, "scale": strength,
                               "two_sided": True}
    else:
        t.roles["material"] = {"type": "diffuse", "reflectance": colour_or_texture(base, owner, reports, t.spectral)}
