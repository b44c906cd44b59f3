#!/usr/bin/env python3
# Which density should a split draw its wavelengths from? A model, not the renderer
# (docs/performance.md, "The split's wavelengths").
#
# In full mode a camera path that enters a dense chromatic medium splits into 4 walks of one bin
# each (integrators/dense_media.h): the bins drawn at 4 equal offsets of one uniform number from a
# density p, each walk's radiance L_i weighted x̄(λ_i)/(4·p(λ_i)) into XYZ. The walks are scaled
# copies of each other that the glass's curved wall parts, so their values correlate only partly:
# measured in the whole-milk glass (docs/performance.md, "How far the split walks can be kept in
# step"), 0.61–0.66 between neighbouring bins and 0.41 between the farthest. The model takes a
# white pixel (every wavelength's mean radiance that of D65 at luminance 1.09, the milk's), each
# walk's relative standard deviation 1, and a correlation
#     rho(λ, λ') = A·exp(−c·|ln(σ_s(λ)/σ_s(λ'))|)
# with σ_s the library's whole milk as a power law (71 000 per m at 400 nm, 20 000 at 700) and A, c
# fitted to those two measurements. It averages the 4 walks' covariance in XYZ over the uniform
# number, and reports the mean CIEDE2000 of a sample's noise (scaled to be small, where ΔE00 is
# linear in it) for candidate densities, as the efficiency relative to the eye-sensitivity density
# pbrt-v4 and hero mode use (1/cosh²(0.0072·(λ − 538 nm))): ΔE00² at equal samples, inverted.
# The spectral part of the noise (a grey walk's colour from 4 wavelengths) is left out: the number
# is stratified over a pixel's samples, so it falls faster than the walks' own.
#
#   bench/split_wavelength_density.py        (numpy; under a second)
import pathlib
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent


def table(name):
    rows = [line.split(",") for line in open(ROOT / "data" / "cie" / name) if line[:1].isdigit()]
    return np.array([[float(x) for x in r] for r in rows])


lam = np.arange(360, 831)
cmf = table("cmf_1931_2deg.csv")
CMF = np.stack([np.interp(lam, cmf[:, 0], cmf[:, k], left=0, right=0) for k in (1, 2, 3)])
d65 = table("illuminant_d65.csv")
WHITE = CMF * np.interp(lam, d65[:, 0], d65[:, 1])
WHITE /= WHITE[1].sum()  # a white of luminance 1, per nm
WHITE_XYZ = WHITE.sum(1)
MEAN_Y = 1.09  # the milk's luminance (docs/performance.md, "Where the whole-milk glass's noise comes from")

exponent = np.log(71000 / 20000) / np.log(700 / 400)
log_sigma = -exponent * np.log(lam / 550.0)
# rho = A·exp(−c·d), d = |ln σ ratio|: 0.635 between neighbours (4 bins at equal offsets of the
# density: about a quarter of the range, d ≈ 0.34) and 0.41 between the farthest (d ≈ 1.28).
c_fit = np.log(0.635 / 0.41) / (1.28 - 0.34)
A_fit = 0.635 * np.exp(c_fit * 0.34)


def lab(xyz):
    t = xyz / WHITE_XYZ
    f = np.where(t > (6 / 29) ** 3, np.cbrt(t), t / (3 * (6 / 29) ** 2) + 4 / 29)
    return np.stack([116 * f[..., 1] - 16, 500 * (f[..., 0] - f[..., 1]), 200 * (f[..., 1] - f[..., 2])], -1)


def ciede2000(lab1, lab2):
    L1, a1, b1 = np.moveaxis(lab1, -1, 0)
    L2, a2, b2 = np.moveaxis(lab2, -1, 0)
    c7 = ((np.hypot(a1, b1) + np.hypot(a2, b2)) / 2) ** 7
    g = 0.5 * (1 - np.sqrt(c7 / (c7 + 25.0**7)))
    a1, a2 = (1 + g) * a1, (1 + g) * a2
    C1, C2 = np.hypot(a1, b1), np.hypot(a2, b2)
    h1, h2 = np.degrees(np.arctan2(b1, a1)) % 360, np.degrees(np.arctan2(b2, a2)) % 360
    dh = (h2 - h1 + 180) % 360 - 180
    dH = 2 * np.sqrt(C1 * C2) * np.sin(np.radians(dh / 2))
    Lm, Cm = (L1 + L2) / 2, (C1 + C2) / 2
    hm = np.where(np.abs(h1 - h2) <= 180, (h1 + h2) / 2, (h1 + h2 + 360) / 2 % 360)
    T = (1 - 0.17 * np.cos(np.radians(hm - 30)) + 0.24 * np.cos(np.radians(2 * hm))
         + 0.32 * np.cos(np.radians(3 * hm + 6)) - 0.20 * np.cos(np.radians(4 * hm - 63)))
    SL = 1 + 0.015 * (Lm - 50) ** 2 / np.sqrt(20 + (Lm - 50) ** 2)
    SC, SH = 1 + 0.045 * Cm, 1 + 0.015 * Cm * T
    RT = -np.sin(np.radians(60 * np.exp(-(((hm - 275) / 25) ** 2)))) * 2 * np.sqrt(Cm**7 / (Cm**7 + 25.0**7))
    dL, dC = (L2 - L1) / SL, (C2 - C1) / SC
    return np.sqrt(dL**2 + dC**2 + (dH / SH) ** 2 + RT * dC * (dH / SH))


def noise(density, strata=256, draws=20000):
    p = density / density.sum()
    cdf = np.cumsum(p)
    cov = np.zeros((3, 3))
    for u in (np.arange(strata) + 0.5) / strata:
        idx = np.minimum(np.searchsorted(cdf, (u + np.arange(4) / 4) % 1.0), len(lam) - 1)
        a = (WHITE[:, idx] / (4 * p[idx])).T  # each walk's weight into XYZ
        d = np.abs(log_sigma[idx][:, None] - log_sigma[idx][None, :])
        rho = np.where(d < 1e-12, 1.0, A_fit * np.exp(-c_fit * d))
        cov += a.T @ rho @ a
    cov *= (MEAN_Y * 1e-2) ** 2 / strata  # small, where ΔE00 is linear in the noise
    mean = WHITE_XYZ * MEAN_Y
    z = np.random.default_rng(1).standard_normal((draws, 3)) @ np.linalg.cholesky(cov).T
    return ciede2000(lab(mean)[None, :], lab(mean + z)).mean()


x, y, z = CMF
candidates = {
    "eye sensitivity (pbrt-v4, hero mode)": 1 / np.cosh(0.0072 * (lam - 538.0)) ** 2,
    "uniform": np.ones(lam.size),
    "x̄ + ȳ + z̄": x + y + z,
    "sqrt(x̄ + ȳ + z̄)": np.sqrt(x + y + z),
    "sqrt(x̄ + ȳ + z̄/2) (the split's)": np.sqrt(x + y + 0.5 * z),
    "sqrt(x̄ + ȳ + z̄/4)": np.sqrt(x + y + 0.25 * z),
    "(x̄ + ȳ + z̄/2)^0.4": (x + y + 0.5 * z) ** 0.4,
    "(x̄ + ȳ + z̄/2)^0.6": (x + y + 0.5 * z) ** 0.6,
    "(x̄ + 2ȳ + 3z̄/4)^0.6": (x + 2 * y + 0.75 * z) ** 0.6,
}
print(f"correlation model: rho = {A_fit:.3f}·exp(−{c_fit:.3f}·|ln σ ratio|); σ_s ∝ λ^−{exponent:.2f}")
base = None
for name, density in candidates.items():
    e = noise(density)
    base = base or e
    print(f"{name:40s} efficiency {(base / e) ** 2:5.2f}")
