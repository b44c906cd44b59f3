#!/usr/bin/env python3
"""The glass of whole milk at #37's terms (240x180, SECONDS of rendering on THREADS cores), noisy and
denoised (--denoise), against a reference of the glass's centre.

Two renders (seeds 1 and 2) of bench/scenes.py's `milk`, each writing its denoised image and the
noisy one beside it (--noisy-output); then two references of the centre of the same frame, each
rendered for REF_SECONDS: the middle 40x30 pixels (seed 1001) and the middle 20x16 (seed 2002),
each a pinhole of the same eye and the angle that makes its pixels the frame's own (a crop of a
pinhole image is a pinhole image of a narrower angle, shifted as a view camera's lens where the
crop is off centre: pixel for pixel the frame's). The references are averaged, weighted by their
samples, over the 20x16 they share; their own gap says how noisy that reference is. A third, of
40x30 pixels at (46, 22) (seed 3003, EDGE_SECONDS), holds the glass's left side and its rim against
the sweep: where a denoiser blurs, if anywhere. Every ΔE00 is `bouguer compare --json` on images cut
out here.
Reports only; the figures are in docs/performance.md ("Denoising the whole-milk glass").
    /usr/bin/python3 bench/denoised_milk.py build/bouguer [--seconds 600] [--ref-seconds 1500]
        [--edge-seconds 1200] [--out DIR]
"""
import argparse
import json
import math
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

REPO = pathlib.Path(__file__).resolve().parent.parent


def read_pfm(path):
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF"
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4").reshape(h, w, 3)
    return np.flipud(data).astype(np.float32)  # row 0 at the top


def write_pfm(path, image):
    h, w, _ = image.shape
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        f.write(np.ascontiguousarray(np.flipud(image), dtype="<f4").tobytes())


def compare(binary, a, b, folder):
    pa, pb = folder / "cmp_a.pfm", folder / "cmp_b.pfm"
    write_pfm(pa, a)
    write_pfm(pb, b)
    out = subprocess.run([binary, "compare", str(pa), str(pb), "--json"], check=True, capture_output=True, text=True)
    j = json.loads(out.stdout)
    return j["mean"], j["mean_lightness"], j["mean_colour"]


def render(binary, scene, folder, name, seconds, seed, threads, extra=()):
    stats = folder / f"{name}.json"
    subprocess.run([binary, "render", str(scene), "--time", str(seconds), "--seed", str(seed), "--threads",
                    str(threads), "--quiet", "-o", str(folder / f"{name}.pfm"), "--stats-json", str(stats), *extra],
                   check=True)
    return json.loads(stats.read_text())


def main():
    p = argparse.ArgumentParser()
    p.add_argument("binary")
    p.add_argument("--seconds", type=float, default=600.0)
    p.add_argument("--ref-seconds", type=float, default=1500.0)
    p.add_argument("--edge-seconds", type=float, default=1200.0)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--out", type=pathlib.Path, default=None)
    a = p.parse_args()
    binary = str(pathlib.Path(a.binary).resolve())
    folder = a.out or pathlib.Path(tempfile.mkdtemp(prefix="denoised_milk_"))
    folder.mkdir(parents=True, exist_ok=True)
    subprocess.run([sys.executable, str(REPO / "bench" / "scenes.py"), str(folder), "milk"], check=True)
    scene = json.loads((folder / "milk.json").read_text())
    width, height = scene["camera"]["resolution"]
    fov = scene["camera"]["fov_deg"]  # across the shorter side, the height here
    assert height <= width

    rows = []
    for seed in (1, 2):
        s = render(binary, folder / "milk.json", folder, f"denoised_{seed}", a.seconds, seed, a.threads,
                   ["--denoise", "--noisy-output", str(folder / f"noisy_{seed}.pfm")])
        rows.append((seed, s["spp"], s["seconds"], s["denoise"]["seconds"]))

    crops = {}  # name: (x0, y0, w, h, spp)
    for name, x0, y0, w, h, seed, seconds in (
            ("centre_40x30", (width - 40) // 2, (height - 30) // 2, 40, 30, 1001, a.ref_seconds),
            ("centre_20x16", (width - 20) // 2, (height - 16) // 2, 20, 16, 2002, a.ref_seconds),
            ("edge_40x30", 46, 22, 40, 30, 3003, a.edge_seconds)):
        c = json.loads(json.dumps(scene))
        c["camera"]["resolution"] = [w, h]
        c["camera"]["fov_deg"] = 2 * math.degrees(math.atan(math.tan(math.radians(fov / 2)) * h / height))
        # The window's centre moved from the frame's, in units of the crop's shorter side (+y up).
        c["camera"]["shift"] = [(x0 + w / 2 - width / 2) / h, (height / 2 - (y0 + h / 2)) / h]
        (folder / f"{name}.json").write_text(json.dumps(c))
        s = render(binary, folder / f"{name}.json", folder, name, seconds, seed, a.threads)
        crops[name] = (x0, y0, w, h, s["spp"])

    noisy = [read_pfm(folder / f"noisy_{s}.pfm") for s in (1, 2)]
    denoised = [read_pfm(folder / f"denoised_{s}.pfm") for s in (1, 2)]
    big, small = read_pfm(folder / "centre_40x30.pfm"), read_pfm(folder / "centre_20x16.pfm")
    edge = read_pfm(folder / "edge_40x30.pfm")
    ex, ey, ew, eh, edge_spp = crops["edge_40x30"]
    bx, by, _, _, big_spp = crops["centre_40x30"]
    sx, sy, sw, sh, small_spp = crops["centre_20x16"]
    big_part = big[sy - by:sy - by + sh, sx - bx:sx - bx + sw]
    reference = (big_part * big_spp + small * small_spp) / (big_spp + small_spp)

    print(f"{width}x{height}, {a.seconds:.0f} s a render on {a.threads} threads; references of the centre "
          f"{a.ref_seconds:.0f} s each ({big_spp} and {small_spp} spp), of the edge {a.edge_seconds:.0f} s "
          f"({edge_spp} spp)\n")
    print("| seed | spp | seconds rendering | then seconds denoising |")
    print("|---|---|---|---|")
    for seed, spp, seconds, dn in rows:
        print(f"| {seed} | {spp} | {seconds:.1f} | {dn:.2f} |")
    fmt = lambda t: f"{t[0]:.3f} (lightness {t[1]:.3f}, colour {t[2]:.3f})"  # noqa: E731
    print("\n| images compared | mean ΔE00 |")
    print("|---|---|")
    print(f"| noisy, seed 1 against seed 2, whole frame | {fmt(compare(binary, noisy[0], noisy[1], folder))} |")
    print(f"| denoised, seed 1 against seed 2, whole frame | {fmt(compare(binary, denoised[0], denoised[1], folder))} |")
    print(f"| the two references against each other, centre 20x16 | {fmt(compare(binary, big_part, small, folder))} |")
    for s in (0, 1):
        cut = lambda im: im[sy:sy + sh, sx:sx + sw]  # noqa: E731
        print(f"| noisy seed {s + 1} against the reference, centre 20x16 | "
              f"{fmt(compare(binary, cut(noisy[s]), reference, folder))} |")
        print(f"| denoised seed {s + 1} against the reference, centre 20x16 | "
              f"{fmt(compare(binary, cut(denoised[s]), reference, folder))} |")
        cutb = lambda im: im[by:by + 30, bx:bx + 40]  # noqa: E731
        print(f"| denoised seed {s + 1} against the 40x30 reference alone, centre 40x30 | "
              f"{fmt(compare(binary, cutb(denoised[s]), big, folder))} |")
        cute = lambda im: im[ey:ey + eh, ex:ex + ew]  # noqa: E731
        print(f"| noisy seed {s + 1} against the edge's reference, edge 40x30 | "
              f"{fmt(compare(binary, cute(noisy[s]), edge, folder))} |")
        print(f"| denoised seed {s + 1} against the edge's reference, edge 40x30 | "
              f"{fmt(compare(binary, cute(denoised[s]), edge, folder))} |")
    print(f"\nimages in {folder}")


if __name__ == "__main__":
    main()
