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


if __name__ == "__main__":
    main()
