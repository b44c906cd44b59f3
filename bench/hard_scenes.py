#!/usr/bin/env python3
"""#37's four benchmarks: time to a mean ΔE00 below 1, this build against an older one.

    bench/hard_scenes.py [NEW [BASE]] [--scenes ball caustic tumbler milk softbox] [--threads 2]

NEW is a bouguer executable (build/bouguer by default). BASE is another, or a git revision to
build one from (a git worktree with a Release build of bouguer in build-base-REVISION/ at the
repository's root, which git ignores, kept for the next run); by default c4d0b2d, the commit #37 was filed
against (the one before its first). The scenes are bench/scenes.py's: the scattering ball,
the red glass ball under a 5 mm spherical lamp, the lit tumbler and the glass of whole milk (by
default), and the lit tumbler under a small softbox and bulb (`--scenes softbox`).

Per scene: one reference, rendered by NEW with the scene's reference estimator at many samples
(seed 1000; the lit tumbler's is NEW's path tracer with its light paths, its ground truth, which
NEW also runs beside the others); then path, bdpt and vcm of each build at doubling sample counts from the scene's first
(seed 1), the two builds alternating at every count (which goes first alternates too), until a
render's mean ΔE00 to the reference is below 1, its time passes the scene's limit or its count passes
--max-spp. The time to ΔE00 1 is read between the two renders on either side of it (on a straight
line in log time against log ΔE00); a run that never got there is extrapolated from its last two
renders (marked "extrapolated"), unless its error had all but stopped falling (slope above
−0.15: "stalls", a bias or a tail far heavier than noise's; no time). The reference's own error
adds to every figure (about as √(e² + e_ref²)); both builds are measured against the same
reference, so it moves both.

One reference for both builds: both are unbiased estimators of the same scene, except where a
build is not (BASE's path tracer reaches no light through the glass from a point or spot lamp: on
the tumbler it converges to a darker liquid, and its ΔE00 stops falling; that is the point). The
caustic's lamp is an exact sphere in NEW and a 48-segment tessellation in BASE (the same scene file;
their converged images are a mean ΔE00 0.7 apart at 2048 spp, that count's noise,
docs/performance.md).

Times are the render's wall seconds from --stats-json (scene set-up excluded), on --threads
threads. Reports only; the figures go in docs/performance.md.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scenes  # noqa: E402  (bench/scenes.py)

# "path+light_paths": the path tracer with its light paths (the scene's "light_paths": true), the
# lit tumbler's ground truth (docs/rendering.md): the path tracer alone leaves out the light the
# glass reflects before it scatters (6.5 % of the liquid), so it is no reference there. NEW runs it
# beside the others where it is the reference; BASE has no light paths.
# resolution, the reference's estimator and samples, the first count of the doubling runs, and the
# longest render a run may take before it stops (seconds at 2 threads; the whole-milk glass never
# reaches 1 within reach, and its runs are extrapolated)
CONFIG = {
    "ball": ("64x64", "path", 16384, 4, 30),
    "caustic": ("64x64", "path", 8192, 1, 30),
    "tumbler": ("64x64", "path+light_paths", 4096, 4, 30),
    "milk": ("32x24", "path", 2048, 16, 30),
    "softbox": ("64x48", "path", 8192, 4, 30),
}
ESTIMATORS = ("path", "bdpt", "vcm")


def render(binary, scene, estimator, spp, seed, resolution, threads, out):
    stats = out + ".stats.json"
    if estimator == "path+light_paths":
        estimator, scene = "path", os.path.splitext(scene)[0] + "-light-paths.json"
    subprocess.run([binary, "render", scene, "--integrator", estimator, "--spp", str(spp), "--seed", str(seed),
                    "--resolution", resolution, "--threads", str(threads), "--quiet", "-o", out,
                    "--stats-json", stats], check=True)
    return json.load(open(stats))["seconds"]


def mean_de(compare_with, a, b):
    result = subprocess.run([compare_with, "compare", a, b, "--json"], check=True, capture_output=True, text=True)
    return json.loads(result.stdout)["mean"]


def time_to_one(points):
    """Seconds to mean ΔE00 1 from (seconds, ΔE00) pairs in sample order, and how it was found."""
    for (t1, e1), (t2, e2) in zip(points, points[1:]):
        if e1 >= 1 > e2:
            slope = math.log(e2 / e1) / math.log(t2 / t1)
            return t1 * math.exp(math.log(1 / e1) / slope), "interpolated"
    if points[0][1] < 1:
        t, e = points[0]
        return t * e * e, "from the first render, as 1/√t"
    (t1, e1), (t2, e2) = points[-2:] if len(points) > 1 else (points[0], points[0])
    slope = math.log(e2 / e1) / math.log(t2 / t1) if t2 > t1 else -0.5
    if slope > -0.15:  # hardly falling: a bias (light it does not reach) or a very heavy tail
        return math.inf, "stalls at ΔE00 %.2f (slope %.2f)" % (e2, slope)
    slope = max(slope, -1.0)
    return t2 * math.exp(math.log(1 / e2) / slope), "extrapolated (slope %.2f)" % slope


def bench_scene(name, builds, args, tmp):
    resolution, ref_estimator, ref_spp, first_spp, max_seconds = CONFIG[name]
    path = os.path.join(tmp, name + ".json")
    json.dump(scenes.scene(name), open(path, "w"))
    with_light_paths = scenes.scene(name)
    with_light_paths.setdefault("render", {})["light_paths"] = True
    json.dump(with_light_paths, open(os.path.splitext(path)[0] + "-light-paths.json", "w"))
    estimators = ESTIMATORS + ((ref_estimator,) if ref_estimator not in ESTIMATORS else ())
    new = builds[0][1]
    reference = os.path.join(tmp, name + "-reference.pfm")
    seconds = render(new, path, ref_estimator, ref_spp, 1000, resolution, args.threads, reference)
    print("\n## %s (%s; reference: NEW %s, %d spp, %.0f s)\n" % (name, resolution, ref_estimator, ref_spp, seconds))
    print("| build | estimator | spp | seconds | mean ΔE00 |")
    print("|---|---|---|---|---|")
    sys.stdout.flush()
    points = {(b, e): [] for b, _ in builds for e in estimators if e in ESTIMATORS or b == "NEW"}
    active = set(points)
    spp, level = first_spp, 0
    while active:
        order = builds if level % 2 == 0 else builds[::-1]
        for estimator in estimators:
            for label, binary in order:
                if (label, estimator) not in active:
                    continue
                out = os.path.join(tmp, "render.pfm")
                t = render(binary, path, estimator, spp, 1, resolution, args.threads, out)
                e = mean_de(new, out, reference)
                points[(label, estimator)].append((t, e))
                print("| %s | %s | %d | %.2f | %.3f |" % (label, estimator, spp, t, e))
                sys.stdout.flush()
                if e < 1 or t > max_seconds or spp * 2 > args.max_spp:
                    active.discard((label, estimator))
        spp *= 2
        level += 1
    print("\n| build | estimator | seconds to mean ΔE00 < 1 | how |")
    print("|---|---|---|---|")
    best = {}
    for (label, estimator), pts in points.items():
        t, how = time_to_one(pts)
        print("| %s | %s | %.1f | %s |" % (label, estimator, t, how))
        if label not in best or t < best[label][0]:
            best[label] = (t, estimator)
    (tn, en), (tb, eb) = best[builds[0][0]], best[builds[1][0]]
    print("\nbest: NEW %s %.1f s, BASE %s %.1f s: %.2f× shorter" % (en, tn, eb, tb, tb / tn))
    sys.stdout.flush()


def base_executable(base):
    """BASE as an executable: itself, or bouguer built at that git revision."""
    if os.path.isfile(base) and os.access(base, os.X_OK):
        return os.path.realpath(base)
    repo = scenes.REPO
    revision = subprocess.run(["git", "-C", repo, "rev-parse", "--short", base + "^{commit}"], check=True,
                              capture_output=True, text=True).stdout.strip()
    tree = os.path.join(repo, "build-base-" + revision)
    binary = os.path.join(tree, "build", "bouguer")
    if not os.path.exists(binary):
        if not os.path.exists(tree):
            subprocess.run(["git", "-C", repo, "worktree", "add", "--detach", tree, revision], check=True)
        subprocess.run(["cmake", "-S", tree, "-B", os.path.join(tree, "build"), "-G", "Ninja",
                        "-DCMAKE_BUILD_TYPE=Release"], check=True, stdout=subprocess.DEVNULL)
        subprocess.run(["cmake", "--build", os.path.join(tree, "build"), "--target", "bouguer"], check=True)
    return binary


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("new", nargs="?", default=os.path.join(scenes.REPO, "build", "bouguer"))
    parser.add_argument("base", nargs="?", default="c4d0b2d")
    parser.add_argument("--scenes", nargs="+", default=[n for n in CONFIG if n != "softbox"], choices=list(CONFIG))
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--max-spp", type=int, default=65536)
    args = parser.parse_args()
    builds = [("NEW", os.path.realpath(args.new)), ("BASE", base_executable(args.base))]
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.scenes:
            bench_scene(name, builds, args, tmp)


if __name__ == "__main__":
    main()
