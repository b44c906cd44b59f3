#!/usr/bin/env python3
"""The path tracer's light paths (render.light_paths) on #37's lit tumbler (tests/data/lit_tumbler:
a glass tumbler of a dilute scattering liquid under a point and a spot lamp), beside the path
tracer without them and vcm. Each row: seconds of one render (seeds 1 and 2, their mean), the
liquid's mean green over the two (x 30-70 %, y 38-88 % of the frame from its top left), the two
seeds' mean ΔE00 over the liquid (the noise) and noise × √seconds (lower is better). Reports only;
figures in docs/performance.md.

    python3 bench/light_paths.py build/bouguer

SPP (64), RESOLUTION (64x64), THREADS (1) may be set in the environment; LIGHTS=sun lights the
tumbler with a sun from the side, 30° up (irradiance 1, D65), in place of its two lamps."""
import json
import os
import struct
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REGION = (0.30, 0.70, 0.38, 0.88)


def read_pfm(path):
    with open(path, "rb") as f:
        f.readline()
        w, h = (int(v) for v in f.readline().split())
        scale = float(f.readline())
        values = struct.unpack(("<" if scale < 0 else ">") + "f" * (w * h * 3), f.read(w * h * 12))
    return w, h, values  # rows bottom to top


def crop(src, dst):
    w, h, values = read_pfm(src)
    x0, x1 = int(REGION[0] * w), int(REGION[1] * w)
    r0, r1 = h - int(REGION[3] * h), h - int(REGION[2] * h)
    out = [values[(y * w + x) * 3 + c] for y in range(r0, r1) for x in range(x0, x1) for c in range(3)]
    with open(dst, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (x1 - x0, r1 - r0))
        f.write(struct.pack("<" + "f" * len(out), *out))
    return sum(out[1::3]) / (len(out) // 3)


def main(argv):
    binary = os.path.realpath(argv[1] if len(argv) > 1 else "build/bouguer")
    spp, resolution, threads = os.environ.get("SPP", "64"), os.environ.get("RESOLUTION", "64x64"), os.environ.get("THREADS", "1")
    with open(os.path.join(REPO, "tests/data/lit_tumbler/scene.json")) as f:
        scene = json.load(f)
    if os.environ.get("LIGHTS") == "sun":
        scene["lights"] = [{"type": "distant", "direction": [0.8, -0.5, -0.3], "spectrum": "D65", "scale": 1}]
    print("| estimator | spp | seconds (one render) | liquid, mean green | mean ΔE00 (liquid) | ΔE00 × √s |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for label, integrator, light_paths in (("path", "path", False), ("path, light paths", "path", True),
                                               ("vcm", "vcm", False)):
            scene["render"]["light_paths"] = light_paths
            path = os.path.join(tmp, "scene.json")
            with open(path, "w") as f:
                json.dump(scene, f)
            seconds, means = 0.0, []
            for seed in (1, 2):
                out, stats = os.path.join(tmp, "%d.pfm" % seed), os.path.join(tmp, "s.json")
                subprocess.run([binary, "render", path, "--integrator", integrator, "--spectral", "full", "--spp", spp,
                                "--resolution", resolution, "--threads", threads, "--seed", str(seed), "-o", out,
                                "--stats-json", stats, "--quiet"], check=True)
                with open(stats) as f:
                    seconds += json.load(f)["seconds"] / 2
                means.append(crop(out, os.path.join(tmp, "c%d.pfm" % seed)))
            noise = json.loads(subprocess.run([binary, "compare", os.path.join(tmp, "c1.pfm"), os.path.join(tmp, "c2.pfm"),
                                               "--json"], check=True, capture_output=True, text=True).stdout)["mean"]
            print("| %s | %s | %.2f | %.5f | %.3f | %.3f |" % (label, spp, seconds, sum(means) / 2, noise,
                                                              noise * seconds ** 0.5))


if __name__ == "__main__":
    main(sys.argv)
