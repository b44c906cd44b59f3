#!/usr/bin/env python3
"""Zips the Blender add-on package (blender/bouguer_blender) for Blender's add-on installer: the
package folder at the zip's top, Python sources only (no __pycache__)."""
import pathlib
import sys
import zipfile

source, target = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
tmp = target.with_suffix(".zip.tmp")
with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
    for path in sorted(source.rglob("*.py")):
        z.write(path, pathlib.Path(source.name) / path.relative_to(source))
tmp.replace(target)
print(f"{target}: {len(zipfile.ZipFile(target).namelist())} files")
