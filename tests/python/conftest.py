"""Shared pieces of the Python module's tests: the built command line, the source tree, a small scene."""
import copy
import os
import pathlib

import numpy as np
import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("BOUGUER_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BINARY = os.environ.get("BOUGUER_BINARY", str(SOURCE_DIR / "build" / "bouguer"))

# A red-glass ball and a light-blue-glass slab over a lit quad: absorption, refraction, an emitter.
SMALL_SCENE = {
    "camera": {"type": "pinhole", "position": [0, "60 mm", "120 mm"], "look_at": [0, 0, 0], "up": [0, 1, 0],
               "fov_deg": 30, "resolution": [24, 16]},
    "render": {"integrator": "path", "spectral": "rgb3", "spp": 4, "max_depth": 8, "seed": 3},
    "world_medium": "air",
    "media": {"glass": {"ior": 1.52, "absorption": {"library": "red-glass"}},
              "blue": {"ior": 1.5, "absorption": {"library": "light-blue-glass"}}},
    "objects": [
        {"name": "ball", "shape": {"type": "sphere", "radius": "12 mm"}, "inside": "glass",
         "transform": [{"translate": ["-15 mm", 0, 0]}]},
        {"name": "slab", "shape": {"type": "box", "size": ["20 mm", "20 mm", "8 mm"]}, "inside": "blue",
         "transform": [{"translate": ["15 mm", 0, 0]}]},
        {"name": "light", "shape": {"type": "quad", "size": ["300 mm", "300 mm"]},
         "transform": [{"rotate_deg": [-90, [1, 0, 0]]}, {"translate": [0, "-30 mm", 0]}],
         "emission": {"spectrum": "D65", "scale": 1.0}},
    ],
    "background": {"spectrum": "E", "scale": 0.2},
}


def read_pfm(path):
    """A colour PFM (as io/pfm.cpp writes it) as a float32 (H, W, 3) array, row 0 at the top."""
    data = pathlib.Path(path).read_bytes()
    header = data.split(b"\n", 3)
    assert header[0] == b"PF"
    width, height = (int(v) for v in header[1].split())
    scale = float(header[2])
    pixels = np.frombuffer(header[3], dtype="<f4" if scale < 0 else ">f4", count=width * height * 3)
    return np.flipud(pixels.reshape(height, width, 3)).astype(np.float32)


@pytest.fixture
def small_scene():
    return copy.deepcopy(SMALL_SCENE)
