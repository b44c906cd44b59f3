#!/usr/bin/env python3
"""The benchmark scenes of #37, in one place (bench/manifold.sh, bench/guiding.sh,
bench/whole_milk_glass.sh, bench/shell_transport.sh, bench/dense_connections.sh,
bench/milk_noise.sh and bench/hard_scenes.py write theirs from here).

    python3 bench/scenes.py OUTDIR NAME...     writes OUTDIR/NAME.json for each NAME

  ball     a ball of scattering medium inside a refracting boundary (n = 1.33, σ_s 30/12/6 per m at
           450/550/650 nm, g 0.7, radius 50 mm) on a grey floor under a 200 mm square lamp: every
           scattering event inside reaches the lamp through one crossing
  caustic  tests/data/red_ball_lamp: a 20 mm red glass ball under a 5 mm spherical lamp (the caustic
           and the coloured shadow under the ball come through two crossings), max_depth 16
  tumbler  tests/data/lit_tumbler: a glass tumbler of a dilute scattering liquid lit by a point and a
           spot lamp (light reaches the liquid only through the glass)
  softbox  the lit tumbler with its point and spot lamp replaced by lamps of size: a 20 mm square
           softbox (two-sided) and a 5 mm emitting sphere (its light reaches the liquid through the
           glass by the walks' refracted directions, and through chains of mesh faces)
  milk     the whole-milk tumbler of scenes/showcase/milk-and-juice.json alone on its sweep under the
           studio map, framed so that it fills most of the picture (#20's glass of whole milk)
  milk_lamp  the same glass of milk with a point lamp (tungsten, up and to the right, whose light
           reaches the milk only through the glass: next-event estimation solves the refractions)
  milk_sun   the same with a sun (D65, which lights the sweep, and the milk through its open top
           and through the glass's wall)
  glassware  scenes/examples/studio-glassware.json: a cobalt ball, a yellow glass block and a
           tumbler of red wine on a white sweep under the studio map (the product shot)
  glassware_mr, glassware_metal, glassware_gloss  the product shot with its sweep glTF's
           metallic-roughness (30 % metal, roughness 0.5), a rough metal (metallic 1, roughness
           0.6) and a glossier one (roughness 0.3): the map's lobes at reflecting surfaces
  glassware_frosted  the product shot with every interface of its three objects rough (α 0.2; the
           wine's surface too)
  frosted_ball  a close-up of a faintly blue glass ball with rough surfaces (α 0.3) under the studio map
  bounce   a floor lit only by a small white patch that a lamp below it shines on (guiding's
           textbook case)
  rod      a lying rod of absorbing glass (an exact cylinder, 20 mm radius, 300 mm long, n = 1.5)
           30 mm above a diffuse floor, a point lamp to one side: the rod's shadow and the caustic
           line in it come through the side, in and out (the ManifoldNextEvent test's scene at
           128×128 pixels, 16 spp)

Paths inside the scenes (the studio map) are made absolute, so OUTDIR may be anywhere.
"""
import copy
import json
import os
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _load(relative):
    path = os.path.join(REPO, relative)
    scene = json.load(open(path))
    env = scene.get("background", {}).get("environment")
    if env:
        scene["background"]["environment"] = os.path.normpath(os.path.join(os.path.dirname(path), env))
    return scene


def ball():
    return {
        "camera": {"position": [0, 0.12, 0.32], "look_at": [0, 0.05, 0], "fov_deg": 35, "resolution": [96, 72]},
        "render": {"integrator": "path", "spectral": "full", "max_depth": 256},
        "world_medium": "vacuum",
        "media": {"milky": {"ior": 1.33, "scattering": {
            "unit": "attenuation_per_m", "wavelength_nm": [450, 550, 650], "value": [30, 12, 6],
            "phase": {"type": "henyey_greenstein", "g": 0.7}}}},
        "objects": [
            {"name": "floor", "shape": {"type": "quad", "size": [2, 2]}, "transform": [{"rotate_deg": [-90, [1, 0, 0]]}],
             "material": {"type": "diffuse", "reflectance": 0.5}},
            {"name": "ball", "shape": {"type": "sphere", "radius": "50 mm"}, "transform": [{"translate": [0, 0.05, 0]}],
             "inside": "milky"},
            {"name": "lamp", "shape": {"type": "quad", "size": [0.2, 0.2]},
             "transform": [{"rotate_deg": [90, [1, 0, 0]]}, {"translate": [0.05, 0.35, 0.05]}],
             "emission": {"spectrum": "D65", "scale": 20}}],
        "background": {"spectrum": "E", "scale": 0}}


def caustic():
    scene = _load("tests/data/red_ball_lamp/scene.json")
    scene["render"]["max_depth"] = 16
    return scene


def tumbler():
    scene = _load("tests/data/lit_tumbler/scene.json")
    scene["camera"]["resolution"] = [64, 64]
    return scene


def softbox():
    scene = tumbler()
    del scene["lights"]
    scene["objects"] += [
        {"name": "softbox", "shape": {"type": "quad", "size": ["20 mm", "20 mm"]},
         "transform": [{"rotate_deg": [90, [0, 1, 0]]}, {"translate": ["-150 mm", "30 mm", "40 mm"]}],
         "emission": {"spectrum": "D65", "scale": 20, "two_sided": True}},
        {"name": "bulb", "shape": {"type": "sphere", "radius": "5 mm"},
         "transform": [{"translate": ["150 mm", "60 mm", "-60 mm"]}], "emission": {"spectrum": "A", "scale": 10}}]
    return scene


def milk():
    scene = _load("scenes/showcase/milk-and-juice.json")
    scene["objects"] = [o for o in scene["objects"] if "skimmed" not in o["name"] and "orange" not in o["name"]]
    for o in scene["objects"]:
        if "whole milk" in o["name"]:
            o["transform"] = []
    scene["camera"]["position"] = [0, "120 mm", "190 mm"]
    scene["camera"]["look_at"] = [0, "45 mm", 0]
    scene["camera"]["fov_deg"] = 30
    return scene


def milk_lamp():
    scene = milk()
    scene["lights"] = [{"type": "point", "position": ["120 mm", "160 mm", "120 mm"], "spectrum": "A", "scale": 0.5}]
    return scene


def milk_sun():
    scene = milk()
    scene["lights"] = [{"type": "distant", "direction": [-0.4, -1, -0.3], "spectrum": "D65", "scale": 2}]
    return scene


def glassware():
    return _load("scenes/examples/studio-glassware.json")


def _glassware_sweep(pbr):
    """The product shot with its sweep made of glTF's metallic-roughness material `pbr`."""
    scene = glassware()
    for o in scene["objects"]:
        if o["name"] == "white sweep":
            del o["material"]
            o["pbr"] = pbr
    return scene


def glassware_mr():  # part metal: the metallic-roughness BRDF itself
    return _glassware_sweep({"base_color": [0.8, 0.8, 0.8], "metallic": 0.3, "roughness": 0.5})


def glassware_metal():  # metallic 1: a rough conductor
    return _glassware_sweep({"base_color": [0.9, 0.9, 0.9], "metallic": 1, "roughness": 0.6})


def glassware_gloss():  # a glossier conductor
    return _glassware_sweep({"base_color": [0.8, 0.8, 0.8], "metallic": 1, "roughness": 0.3})


def glassware_frosted():  # every interface of the three objects rough (GGX α 0.2), the wine's surface too
    scene = glassware()
    for o in scene["objects"]:
        if "inside" in o:
            o["roughness"] = 0.2
    return scene


def frosted_ball():
    """A close-up of a faintly blue glass ball with rough surfaces (GGX α 0.3) under the studio map."""
    studio = glassware()["background"]
    return {
        "camera": {"position": [0, 0, 0.1], "look_at": [0, 0, 0], "fov_deg": 30, "resolution": [64, 64]},
        "render": {"integrator": "path", "spectral": "full", "max_depth": 64},
        "world_medium": "vacuum",
        "media": {"glass": {"ior": 1.5, "absorption": {"unit": "attenuation_per_m", "wavelength_nm": [380, 780],
                                                         "value": [5, 20]}}},
        "objects": [{"name": "ball", "shape": {"type": "sphere", "radius": "20 mm"}, "inside": "glass",
                     "roughness": 0.3}],
        "background": studio}


def bounce():
    return {
        "camera": {"position": [0, 0.6, 1.2], "look_at": [0, 0, 0], "fov_deg": 40, "resolution": [96, 72]},
        "render": {"integrator": "path", "spectral": "hero", "max_depth": 8},
        "objects": [
            {"name": "floor", "shape": {"type": "quad", "size": [2, 2]}, "transform": [{"rotate_deg": [-90, [1, 0, 0]]}],
             "material": {"type": "diffuse", "reflectance": 0.6}},
            {"name": "patch", "shape": {"type": "quad", "size": [0.15, 0.15]},
             "transform": [{"rotate_deg": [90, [1, 0, 0]]}, {"translate": [0, 0.6, 0]}],
             "material": {"type": "diffuse", "reflectance": 0.9}},
            {"name": "lamp", "shape": {"type": "quad", "size": [0.03, 0.03]},
             "transform": [{"rotate_deg": [-90, [1, 0, 0]]}, {"translate": [0, 0.4, 0]}],
             "emission": {"spectrum": "D65", "scale": 2000}}],
        "background": {"spectrum": "E", "scale": 0}}


def rod():
    return {
        "camera": {"type": "orthographic", "position": [0, 0.3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1],
                   "width": 0.12, "resolution": [128, 128]},
        "render": {"integrator": "path", "spectral": "full", "spp": 16, "max_depth": 16, "seed": 1},
        "world_medium": "vacuum",
        "media": {"glass": {"ior": 1.5, "absorption": {"unit": "attenuation_per_m", "wavelength_nm": [380, 780],
                                                         "value": [20, 30]}}},
        "objects": [
            {"name": "floor", "shape": {"type": "quad", "size": [1, 1]}, "transform": [{"rotate_deg": [-90, [1, 0, 0]]}],
             "material": {"type": "diffuse", "reflectance": 0.8}},
            {"name": "rod", "shape": {"type": "cylinder", "radius": 0.02, "height": 0.3},
             "transform": [{"translate": [0, -0.15, 0]}, {"rotate_deg": [90, [1, 0, 0]]}, {"translate": [0, 0.03, 0]}],
             "inside": "glass"}],
        "lights": [{"type": "point", "position": [0.1, 0.1, 0.01], "spectrum": "D65", "scale": 0.02}],
        "background": {"spectrum": "E", "scale": 0}}


SCENES = {"ball": ball, "caustic": caustic, "tumbler": tumbler, "softbox": softbox, "milk": milk,
          "milk_lamp": milk_lamp, "milk_sun": milk_sun, "glassware": glassware,
          "glassware_mr": glassware_mr, "glassware_metal": glassware_metal, "glassware_gloss": glassware_gloss,
          "glassware_frosted": glassware_frosted, "frosted_ball": frosted_ball, "bounce": bounce, "rod": rod}


def scene(name):
    return copy.deepcopy(SCENES[name]())


def main(argv):
    if len(argv) < 3 or any(name not in SCENES for name in argv[2:]):
        sys.exit("usage: scenes.py OUTDIR NAME... (names: %s)" % " ".join(SCENES))
    for name in argv[2:]:
        with open(os.path.join(argv[1], name + ".json"), "w") as f:
            json.dump(scene(name), f, indent=1)


if __name__ == "__main__":
    main(sys.argv)
