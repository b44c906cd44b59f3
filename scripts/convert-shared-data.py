#!/usr/bin/env python3
"""Converts source tables from ../shared/data into Bouguer's own data files (data/).

Run by hand when a source table changes; the build never runs it and the product never reads
../shared. Values are copied as the source prints them (no re-rounding); only the layout changes:
a '#' comment block naming the source, a header row `wavelength_nm,<quantity>...`, and rows trimmed
to Bouguer's wavelength domain, 360-830 nm.
"""
import csv
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
SHARED = ROOT.parent / "shared" / "data"
DOMAIN_NM = (360, 830)

CIE_LICENCE = "Licence: CC BY-SA 4.0 (CIE); this converted table is shared under the same licence."


def read_rows(path):
    with open(path, newline="") as f:
        return [row for row in csv.reader(f) if row]


def write_table(out, comments, header, rows):
    out.parent.mkdir(parents=True, exist_ok=True)
    with open(out, "w", newline="\n") as f:
        for c in comments:
            f.write(f"# {c}\n")
        f.write(",".join(header) + "\n")
        for r in rows:
            f.write(",".join(r) + "\n")
    print(f"wrote {out.relative_to(ROOT)} ({len(rows)} rows)")


def in_domain(row):
    return DOMAIN_NM[0] <= float(row[0]) <= DOMAIN_NM[1]


def convert_cmf(src, out, title, doi, nan_as_zero):
    rows = []
    for r in read_rows(SHARED / "cie" / src):
        if not in_domain(r):
            continue
        rows.append([v.strip() if v.strip() != "NaN" or not nan_as_zero else "0" for v in r])
    comments = [title,
                f"Source: CIE (2019), DOI {doi}; file {src} as published by the CIE (SHA-256 verified",
                "against the CIE metadata record), staged in shared/data/cie.",
                CIE_LICENCE]
    if nan_as_zero:
        comments.append("The CIE file gives zbar10 as NaN from 556 nm up; the CIE metadata says the")
        comments.append("extrapolation is zero, so NaN is written as 0 here.")
    write_table(ROOT / "data" / "cie" / out, comments, ["wavelength_nm", "xbar", "ybar", "zbar"], rows)


def convert_illuminant(src, out, title, doi, column=1):
    rows = [[r[0].strip(), r[column].strip()] for r in read_rows(SHARED / "cie" / src) if in_domain(r)]
    comments = [title + " (relative spectral power, arbitrary units; Bouguer normalises it to luminance)",
                f"Source: CIE, DOI {doi}; file {src} as published by the CIE, staged in shared/data/cie.",
                CIE_LICENCE]
    write_table(ROOT / "data" / "cie" / out, comments, ["wavelength_nm", "relative_power"], rows)


def main():
    if not SHARED.is_dir():
        sys.exit(f"convert-shared-data: {SHARED} not found (clone beside shared/)")
    convert_cmf("CIE_xyz_1931_2deg.csv", "cmf_1931_2deg.csv",
                "CIE 1931 colour-matching functions, 2 degree observer, 1 nm (CIE 018:2019 Table 6)",
                "10.25039/CIE.DS.xvudnb9b", nan_as_zero=False)
    convert_cmf("CIE_xyz_1964_10deg.csv", "cmf_1964_10deg.csv",
                "CIE 1964 colour-matching functions, 10 degree observer, 1 nm (ISO/CIE 11664-1:2019 Table 2)",
                "10.25039/CIE.DS.sqksu2n5", nan_as_zero=True)
    convert_illuminant("CIE_std_illum_D65.csv", "illuminant_d65.csv",
                       "CIE standard illuminant D65, 1 nm (ISO/CIE 11664-2:2022 Table B.1)",
                       "10.25039/CIE.DS.hjfjmt59")
    convert_illuminant("CIE_std_illum_D50.csv", "illuminant_d50.csv",
                       "CIE illuminant D50, 1 nm (ISO/CIE 11664-2:2022 Table B.1)",
                       "10.25039/CIE.DS.etgmuqt5")
    convert_illuminant("CIE_std_illum_A_1nm.csv", "illuminant_a.csv",
                       "CIE standard illuminant A, 1 nm (Planckian, about 2856 K; ISO/CIE 11664-2:2022 eq. 1)",
                       "10.25039/CIE.DS.8jsxjrsn")
    # Columns of CIE_illum_FLs_1nm.csv: lambda, FL1..FL12, FL3.1..FL3.15.
    for n in (2, 7, 11):
        convert_illuminant("CIE_illum_FLs_1nm.csv", f"illuminant_f{n}.csv",
                           f"CIE illuminant F{n} (FL{n}), 1 nm, 380-780 nm (CIE marks the 1 nm table"
                           " 'approximated', interpolated from the 5 nm CIE 015:2018 Tables 10.1-10.3)",
                           "10.25039/CIE.DS.54hy6srn", column=n)




# ---------------------------------------------------------------------------------------------
# Library materials: absorption as sigma_a_per_m (natural log, per metre) at 1 nm, 360-830 nm.

MATERIAL_LICENCE_APHALO = ("Licence: GPL (>= 2), as the photobiologyFilters R package that carries the "
                           "measurement (P. J. Aphalo).")
LN10 = 2.302585092994046


def read_aphalo(name):
    rows = {}
    for line in open(SHARED / "photobiologyFilters-aphalo" / "measured" / name, encoding="latin-1"):
        parts = line.strip().split(";")
        try:
            rows[int(round(float(parts[0])))] = float(parts[1]) / 100.0
        except (ValueError, IndexError):
            continue
    return rows


def glass_sigma(name, thickness_mm, floor, surfaces=None):
    """Total transmittance of a plate -> internal transmittance -> sigma_a.

    The two surface losses are removed by dividing by the maximum transmittance in 380-830 nm (the
    plateau away from the absorption band). Readings below `floor` are instrument stray light /
    noise and carry no information: they are raised to `floor`, which caps sigma_a."""
    t = read_aphalo(name)
    plateau = surfaces if surfaces else max(v for w, v in t.items() if 380 <= w <= 830)
    out = []
    for w in range(DOMAIN_NM[0], DOMAIN_NM[1] + 1):
        t_int = min(1.0, max(t[w], floor) / plateau)
        out.append((w, -__import__("math").log(t_int) / (thickness_mm * 1e-3)))
    return out, plateau


def write_material(out_name, comments, rows):
    write_table(ROOT / "data" / "materials" / out_name, comments, ["wavelength_nm", "sigma_a_per_m"],
                [[str(w), f"{v:.6g}"] for w, v in rows])


def convert_glasses():
    rows, plateau = glass_sigma("Hoya-25A-HMC-2.3mm-52mm-ABS.csv", 2.3, 0.003)
    write_material("red-glass.csv", [
        "red-glass: Hoya 25A red sharp-cut (long-pass) filter glass, multicoated, 2.3 mm plate;",
        "half-maximum edge near 603 nm. The paper's 'red glass with an abrupt absorption edge' (its Fig. 1)",
        "is only a picture; this is the nearest real measurement available.",
        "Measured: total spectral transmittance (%), Agilent 8453 diode-array spectrophotometer, 1 nm,",
        "single sample, by P. J. Aphalo; file Hoya-25A-HMC-2.3mm-52mm-ABS.csv of the photobiologyFilters",
        "R package (github.com/aphalo/photobiologyfilters, commit f881fb17), staged in",
        "shared/data/photobiologyFilters-aphalo. Cite: Aphalo, P. J. (2015) UV4Plants Bulletin 2015:1, 21-29.",
        f"Conversion: T_internal = T_total / {plateau:.4f} (plateau at 657 nm, removes the coated surfaces),",
        "readings below 0.3 % (the instrument's stray-light plateau at 400-560 nm) raised to 0.3 %, so",
        "sigma_a is capped near 2.5e3 per m there; sigma_a = -ln(T_internal) / 2.3 mm.",
        MATERIAL_LICENCE_APHALO], rows)
    rows, plateau = glass_sigma("Heliopan-BG38-2.3mm-46mm-ABS.CSV", 2.3, 0.0005)
    write_material("light-blue-glass.csv", [
        "light-blue-glass: Heliopan BG38 filter (Schott BG38-type copper phosphate glass), 2.3 mm plate;",
        "a smooth light blue-green absorber rising toward the red, as the paper's 'light blue glass'",
        "(its Fig. 1, only a picture) - the nearest real measurement available.",
        "Measured: total spectral transmittance (%), Agilent 8453, 1 nm, single sample, by P. J. Aphalo;",
        "file Heliopan-BG38-2.3mm-46mm-ABS.CSV of the photobiologyFilters R package (commit f881fb17),",
        "staged in shared/data/photobiologyFilters-aphalo. Cite: Aphalo, P. J. (2015) UV4Plants Bulletin 2015:1.",
        f"Conversion: T_internal = T_total / {plateau:.4f} (maximum, at 504 nm), readings below 0.05 %",
        "(noise floor) raised to 0.05 %; sigma_a = -ln(T_internal) / 2.3 mm.",
        MATERIAL_LICENCE_APHALO], rows)


def read_drink_mix():
    band = {}
    for line in open(SHARED / "phet-beers-law-lab" / "molar_absorptivity_380_780nm.csv"):
        if line.startswith("#") or line.startswith("wavelength"):
            continue
        parts = line.strip().split(",")
        band[int(parts[0])] = float(parts[1])
    peak = max(band.values())
    return {w: v / peak for w, v in band.items()}


def fit_wine(targets):
    """A(lambda) per cm (decadic) = c1 * band(lambda) + c2 * exp(-(lambda - 420) / s).

    band = the measured drink-mix (red dye) molar absorptivity of PhET's Beer's Law Lab, normalised
    to its peak; c1, c2, s solved exactly so that A(420), A(520), A(620) equal the targets."""
    import math
    band = read_drink_mix()

    def solve(s):
        e = lambda w: math.exp(-(w - 420) / s)
        # Two equations (420, 520) in c1, c2.
        a11, a12, b1 = band[420], e(420), targets[420]
        a21, a22, b2 = band[520], e(520), targets[520]
        det = a11 * a22 - a12 * a21
        c1 = (b1 * a22 - a12 * b2) / det
        c2 = (a11 * b2 - b1 * a21) / det
        return c1, c2, c1 * band[620] + c2 * e(620) - targets[620]

    lo, hi = 5.0, 2000.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if (solve(lo)[2] > 0) == (solve(mid)[2] > 0):
            lo = mid
        else:
            hi = mid
    s = 0.5 * (lo + hi)
    c1, c2, residual = solve(s)
    assert abs(residual) < 1e-9 and c1 >= 0 and c2 >= 0, (c1, c2, residual)

    def absorbance(w):
        wb = min(max(w, 380), 780)  # the band is measured 380-780 nm; held at its end values outside
        return c1 * band[wb] + c2 * math.exp(-(w - 420) / s)
    rows = [(w, absorbance(w) * LN10 * 100.0) for w in range(DOMAIN_NM[0], DOMAIN_NM[1] + 1)]
    return rows, (c1, c2, s)


def convert_wines():
    common = [
        "Fitted model, not a measured spectrum (no measured wine spectrum is available): decadic",
        "absorbance per cm A(l) = c1*band(l) + c2*exp(-(l - 420 nm)/s), where band(l) is the measured",
        "molar absorptivity of the red 'drink mix' dye of PhET Beer's Law Lab (phetsims/beers-law-lab,",
        "doc/wavelength-to-molarAbsorptivity.csv, GPL-3.0; staged in shared/data/phet-beers-law-lab),",
        "normalised to its peak at 510 nm, standing in for the anthocyanin band near 520 nm; the",
        "exponential is the yellow-brown (tannin/browning) term. c1, c2, s solve A(420), A(520), A(620)",
        "exactly for the targets below: median Glories absorbances of commercial muscadine wines",
        "(maryserviss/commercial_muscadine_wines, final_ordered_wine_data_rf.csv, commit 77b126a4;",
        "staged in shared/data/wine-muscadine-glories), reported per 1 cm as the OIV method specifies.",
        "Outside 380-780 nm the band is held at its end values. sigma_a = A * ln(10) * 100 per m.",
    ]
    for name, label, targets in (("red-wine", "red wine", {420: 1.94, 520: 1.90, 620: 0.33}),
                                 ("white-wine", "white wine", {420: 0.17, 520: 0.033, 620: 0.006})):
        rows, (c1, c2, s) = fit_wine(targets)
        write_material(f"{name}.csv", [
            f"{name}: {label}."] + common + [
            f"Targets (A per cm): A420 = {targets[420]}, A520 = {targets[520]}, A620 = {targets[620]} "
            f"(medians of the {'15 red' if name == 'red-wine' else '11 white'} wines).",
            f"Fit: c1 = {c1:.6g}, c2 = {c2:.6g}, s = {s:.6g} nm."], rows)


def convert_water():
    rows = []
    for r in read_rows(SHARED / "water" / "ioccg_2018.csv")[1:]:
        if in_domain(r):
            rows.append([r[0].strip(), r[1].strip()])
    write_table(ROOT / "data" / "materials" / "water.csv", [
        "water: pure water, absorption coefficient a_w (natural log, per metre), 5 nm, 360-830 nm.",
        "Measured (consensus compilation): IOCCG Protocol Series (2018), Inherent Optical Property",
        "Measurements and Protocols: Absorption Coefficient, Neeley & Mannino (eds.), IOCCG Ocean Optics and",
        "Biogeochemistry Protocols for Satellite Ocean Colour Sensor Validation, Vol. 1.0; stitched from",
        "Morel et al. 2007 (360-415 nm), Pope & Fry 1997 (420-725 nm, integrating cavity, doi:10.1364/AO.36.008710)",
        "and Kou, Labrie & Chylek 1993 (730-830 nm). File ioccg_2018.csv of raphidoc/aw (commit d20909b0),",
        "staged in shared/data/water; column a_w copied as printed. Pure water at about 20-22 degC, no salt.",
        "Licence: the numbers are published measurements; the carrying repository is MIT (c) 2025 Raphael Mabit.",
    ], ["wavelength_nm", "sigma_a_per_m"], rows)


# Uncoated glass of n = 1.52 at normal incidence, both surfaces with their multiple reflections:
# T = 2n / (n^2 + 1). Used where no band-free plateau exists to calibrate against.
UNCOATED_152 = 2 * 1.52 / (1.52 ** 2 + 1)

MORE_GLASSES = [
    # out name, source file, thickness mm, floor, surfaces (None: plateau), description
    ("orange-glass.csv", "Heliopan-Orange-22-SH-PMC-2.2mm-52mm-ABS.csv", 2.2, 0.0005, None,
     "orange-glass: Heliopan 22 orange sharp-cut filter glass, coated, 2.2 mm plate; edge near 568 nm."),
    ("deep-red-glass.csv", "Heliopan-RG665-2.3mm-46mm-ABS.CSV", 2.3, 0.0005, None,
     "deep-red-glass: Heliopan filter of Schott RG665 glass, 2.3 mm plate; edge near 651 nm."),
    ("pale-blue-glass.csv", "Hoya-82A-HMC-2.1mm-52mm-ABS.CSV", 2.1, 0.0005, 0.975,
     "pale-blue-glass: Hoya 82A light-balancing glass, multicoated, 2.1 mm plate; 91 % at 400 nm sloping to 70 % at 660 nm."),
    ("yellow-glass.csv", "Tangsinuo-JB450-2.0mm-52mm-ABS.CSV", 2.0, 0.0005, UNCOATED_152,
     "yellow-glass: JB450 yellow long-pass glass (Tangsinuo), uncoated, 2.0 mm plate; edge near 460 nm."),
    ("cobalt-blue-glass.csv", "Tangsinuo-ZB1-2.0mm-52mm-ABS.CSV", 2.0, 0.0005, UNCOATED_152,
     "cobalt-blue-glass: ZB1 violet-blue glass (Tangsinuo), cobalt-like: passes blue and a red/NIR leak above 700 nm; 2.0 mm."),
    ("blue-green-glass.csv", "Tangsinuo-QB21AR-2.0mm-52mm-ABS.CSV", 2.0, 0.0005, None,
     "blue-green-glass: QB21 copper-type blue-green glass (Tangsinuo), AR coated, 2.0 mm plate; half maximum near 620 nm."),
]


def convert_more_glasses():
    for out, src, mm, floor, surfaces, what in MORE_GLASSES:
        rows, plateau = glass_sigma(src, mm, floor, surfaces)
        how = (f"T_internal = T_total / {plateau:.4f} (" +
               ("the maximum over 380-830 nm: coated surfaces" if surfaces is None else
                "0.975: multicoated surfaces, the maximum 0.919 being inside the absorption" if surfaces == 0.975 else
                "2n/(n^2+1) for uncoated n = 1.52 surfaces with multiple reflections") + ")")
        write_material(out, [
            what,
            "Measured: total spectral transmittance (%), Agilent 8453 diode-array spectrophotometer, 1 nm,",
            f"single sample, by P. J. Aphalo; file {src} of the photobiologyFilters",
            "R package (github.com/aphalo/photobiologyfilters, commit f881fb17), staged in",
            "shared/data/photobiologyFilters-aphalo. Cite: Aphalo, P. J. (2015) UV4Plants Bulletin 2015:1, 21-29.",
            f"Conversion: {how}; readings below {floor * 100:g} % (noise floor) raised to it, so sigma_a is",
            f"capped there; sigma_a = -ln(T_internal) / {mm} mm.",
            MATERIAL_LICENCE_APHALO], rows)


PHET_DYES = [
    # out name, column, description
    ("cobalt-chloride.csv", "CoCl2", "cobalt(II) chloride, aqueous (pink)"),
    ("cobalt-nitrate.csv", "CoNO3_2", "cobalt(II) nitrate, aqueous (red-pink)"),
    ("nickel-chloride.csv", "NiCl2", "nickel(II) chloride, aqueous (green)"),
    ("copper-sulfate.csv", "CuSO4", "copper(II) sulfate, aqueous (blue)"),
    ("potassium-dichromate.csv", "K2Cr2O7", "potassium dichromate, aqueous (orange)"),
    ("potassium-chromate.csv", "K2CrO4", "potassium chromate, aqueous (yellow)"),
    ("potassium-permanganate.csv", "KMnO4_sim_2014", "potassium permanganate, aqueous (purple); PhET's revised 2014 data"),
]


def convert_dyes():
    rows = [r for r in read_rows(SHARED / "phet-beers-law-lab" / "molar_absorptivity_380_780nm.csv")
            if not r[0].startswith("#")]
    header, data = rows[0], rows[1:]
    for out, column, what in PHET_DYES:
        k = header.index(column)
        table = [[d[0], f"{LN10 * 100.0 * max(0.0, float(d[k])):.6g}"] for d in data]
        write_table(ROOT / "data" / "materials" / out, [
            f"{out[:-4]}: {what}. Molar: sigma_a per metre per mol/L (the scene's 'concentration' in mol/L).",
            "Measured: decadic molar absorptivity epsilon [L/(mol cm)], 380-780 nm, 1 nm, by J. Chamberlain for",
            "PhET Interactive Simulations (University of Colorado Boulder), 'Beer's Law Lab'",
            f"(github.com/phetsims/beers-law-lab, commit df9701f6), column {column} of",
            "shared/data/phet-beers-law-lab/molar_absorptivity_380_780nm.csv. Teaching-lab data, not a reference",
            "standard (see that SOURCE.txt). Conversion: sigma_a = ln(10) * 100 * epsilon (negative noise -> 0).",
            "Outside 380-780 nm the renderer holds the end values (flagged by bouguer material --info).",
            "Licence: GPL-3.0, as the beers-law-lab repository."], ["wavelength_nm", "sigma_a_per_m_per_mol_l"], table)


def convert_gems():
    import math
    fade_m = 0.005
    rows = read_rows(SHARED / "gems-spectralrender-ive" / "gem_relative_absorption.csv")[1:]
    for gem, out in (("Ruby", "ruby.csv"), ("Emerald", "emerald.csv")):
        table = [[r[1], f"{-math.log(1.0 - min(0.99, float(r[2]))) / fade_m:.6g}"] for r in rows if r[0] == gem]
        write_table(ROOT / "data" / "materials" / out, [
            f"{out[:-4]}: {gem.lower()}, relative absorption curve of Ive's SpectralRender minerals (POV-Ray), 380-730 nm.",
            "NOT a measurement: S_ABS is a renderer-authored relative absorptance of undocumented provenance (see",
            "shared/data/gems-spectralrender-ive/SOURCE.txt); bands are plausible (ruby: Cr3+ near 410 and 550 nm).",
            "Source: syanenko/povgems (commit 7e4d9aea), spectral_minerals.inc by Ive (LILYsoft), public domain.",
            "Conversion: SpectralRender's transmittance is (1 - S_ABS) per 'fade distance', a free parameter;",
            f"here the fade distance is set to {fade_m * 1000:g} mm (a medium stone): sigma_a = -ln(1 - S_ABS) / 5 mm,",
            "S_ABS capped at 0.99 (ruby reaches 1.0 at 380-385 nm, which would be an infinite coefficient).",
            "Outside 380-730 nm the renderer holds the end values (flagged by bouguer material --info)."],
            ["wavelength_nm", "sigma_a_per_m"], table)


def convert_olive_oil():
    table = []
    for line in open(SHARED / "olive-oil-evoodec" / "spectra" / "fresh_evoo.csv"):
        if line.startswith("#") or not line.strip():
            continue
        nm, a = line.strip().split(";")
        table.append((int(float(nm)), max(0.0, float(a))))
    table.sort()
    write_table(ROOT / "data" / "materials" / "olive-oil.csv", [
        "olive-oil: fresh extra-virgin olive oil, measured decadic absorbance of the neat oil, 390-720 nm, 1 nm.",
        "Source: S. Jurinovich and V. Domenici, J. Chem. Educ. 99(2), 787-798 (2022), doi:10.1021/acs.jchemed.1c01015;",
        "file spectra/fresh_evoo.csv of sandroj87/EVOODec (commit 8df8655e), staged in shared/data/olive-oil-evoodec.",
        "The optical path is not recorded; EVOODec assumes 1 cm, taken here: sigma_a = ln(10) * 100 * A.",
        "Negative baseline noise near 720 nm set to 0. Outside 390-720 nm the renderer holds the end values.",
        "Licence: GPL-3.0, as the EVOODec repository."],
        ["wavelength_nm", "sigma_a_per_m"], [[str(w), f"{LN10 * 100.0 * a:.6g}"] for w, a in table])


def convert_beer():
    import math
    coef = {r[0]: float(r[1]) for r in read_rows(SHARED / "beer-delange-model" / "beer_absorbance_model.txt")
            if not r[0].startswith("#") and r[0] != "coefficient"}
    srm = 10.0
    a430 = srm / coef["srm_to_A430_divisor"]
    table = []
    for w in range(DOMAIN_NM[0], DOMAIN_NM[1] + 1):
        x = w - coef["lambda_ref"]
        a = a430 * (coef["w1"] * math.exp(-x / coef["tau1"]) + coef["w2"] * math.exp(-x / coef["tau2"]))
        table.append([str(w), f"{LN10 * 100.0 * a:.6g}"])
    write_table(ROOT / "data" / "materials" / "beer.csv", [
        "beer: an amber beer of colour SRM 10 (EBC 19.7), A. J. deLange's spectral model: FITTED MODEL, the mean",
        "spectral shape of 99 beers, not one measured beer. A(lambda) per cm = A430 (0.02465 exp(-(lambda-430)/17.591)",
        "+ 0.97535 exp(-(lambda-430)/82.122)), A430 = SRM / 12.7. 'concentration' scales the SRM (2 = SRM 20).",
        "Source: A. J. deLange, 'Color', in C. W. Bamforth (ed.), Brewing Materials and Processes, Academic Press",
        "2016, pp. 199-249, doi:10.1016/B978-0-12-799954-8.00011-3; coefficients as recorded in",
        "shared/data/beer-delange-model (read from aschet/olfarve, MIT). Valid 380-780 nm; evaluated here over",
        "360-830 nm (the formula extrapolated, flagged by bouguer material --info). sigma_a = ln(10) * 100 * A."],
        ["wavelength_nm", "sigma_a_per_m"], table)


if __name__ == "__main__":
    main()
    convert_glasses()
    convert_wines()
    convert_water()
    convert_more_glasses()
    convert_dyes()
    convert_gems()
    convert_olive_oil()
    convert_beer()
