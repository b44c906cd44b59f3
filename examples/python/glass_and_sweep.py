#!/usr/bin/env python3
"""Bouguer from Python: the library's glasses by thickness, and a concentration sweep.

Writes two figures into OUT (default: the working directory):
  glass_transmittance.png  internal transmittance at 450, 550 and 650 nm against thickness for
                           every glass of the library, with the slab's colour (bouguer.material);
  concentration_sweep.png  a cuvette of copper sulfate solution rendered at five concentrations,
                           the scene compiled once and its absorption changed in place.

Run with the build folder on PYTHONPATH (docs/python.md):
  PYTHONPATH=build /usr/bin/python3 examples/python/glass_and_sweep.py --out /tmp/figures
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")  # headless: files only
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import bouguer  # noqa: E402

PROBES_NM = np.array([450.0, 550.0, 650.0])

# A cuvette of 10 mm of copper sulfate solution (molar: concentration in mol/L) in front of a lit
# white quad, seen through the glass walls' index (the absorption is the solution's only).
CUVETTE = {
    "camera": {"type": "pinhole", "position": [0, "10 mm", "150 mm"], "look_at": [0, 0, 0], "up": [0, 1, 0],
               "fov_deg": 22, "resolution": [96, 64]},
    "render": {"integrator": "whitted", "spectral": "full", "spp": 8, "max_depth": 12, "seed": 1},
    "world_medium": "air",
    "media": {"solution": {"ior": 1.34, "absorption": {"library": "copper-sulfate", "concentration": 0.1}}},
    "objects": [
        {"name": "cuvette", "shape": {"type": "box", "size": ["40 mm", "30 mm", "10 mm"]}, "inside": "solution"},
        {"name": "backlight", "shape": {"type": "quad", "size": ["200 mm", "200 mm"]},
         "transform": [{"translate": [0, 0, "-40 mm"]}], "emission": {"spectrum": "D65", "scale": 1.0}},
    ],
    "background": {"spectrum": "E", "scale": 0.05},
}


def glasses():
    return [name for name in bouguer.material_names() if name.endswith("glass")]


def plot_transmittance(out):
    thickness_m = np.geomspace(1e-4, 5e-2, 60)
    names = glasses()
    fig, axes = plt.subplots(1, len(PROBES_NM), figsize=(12, 4), sharey=True)
    for name in names:
        glass = bouguer.material(name)
        colour = glass.slab_colour([3e-3])["spectral"]["hex"][0]  # the colour of 3 mm of it
        t = glass.transmittance(PROBES_NM[:, None], thickness_m[None, :])  # (3, 60), broadcast
        for ax, row in zip(axes, t):
            ax.plot(thickness_m * 1e3, row, color=colour, label=name, lw=2)
    for ax, nm in zip(axes, PROBES_NM):
        ax.set_xscale("log")
        ax.set_xlabel("thickness (mm)")
        ax.set_title(f"{nm:g} nm")
    axes[0].set_ylabel("internal transmittance exp(-σ_a d)")
    axes[-1].legend(fontsize=7, loc="lower left")
    fig.suptitle("The library's glasses (line colour: the colour of 3 mm against D65)")
    fig.tight_layout()
    path = out / "glass_transmittance.png"
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return path


def render_sweep(out, factors, resolution, spp):
    scene = bouguer.load_dict(CUVETTE)
    fig, axes = plt.subplots(1, len(factors), figsize=(2.4 * len(factors), 2.2))
    images = []
    for ax, factor in zip(np.atleast_1d(axes), factors):
        scene.set_absorption_scale("solution", factor)  # no recompile: only the spectra change
        rgb = bouguer.render(scene, resolution=resolution, spp=spp)
        images.append(rgb)
        srgb = np.where(rgb <= 0.0031308, 12.92 * rgb, 1.055 * np.power(np.clip(rgb, 0, None), 1 / 2.4) - 0.055)
        ax.imshow(np.clip(srgb, 0, 1))
        ax.set_title(f"{0.1 * factor:g} mol/L", fontsize=9)
        ax.axis("off")
    fig.suptitle("Copper sulfate, 10 mm, rendered at five concentrations")
    fig.tight_layout()
    path = out / "concentration_sweep.png"
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return path, images


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", type=pathlib.Path, default=pathlib.Path("."))
    parser.add_argument("--resolution", type=int, nargs=2, default=[96, 64], metavar=("W", "H"))
    parser.add_argument("--spp", type=int, default=8)
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    print(plot_transmittance(args.out))
    path, _ = render_sweep(args.out, [0.5, 1.0, 2.0, 4.0, 8.0], tuple(args.resolution), args.spp)
    print(path)


if __name__ == "__main__":
    main()
