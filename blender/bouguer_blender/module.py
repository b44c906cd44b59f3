"""Finding the `bouguer` Python module: the add-on's preference (a build folder), the environment
variable BOUGUER_BUILD, or PYTHONPATH (docs/blender.md, "Where the module comes from")."""
import importlib
import os
import sys

import bpy

ADDON = __package__


def module_folder():
    prefs = bpy.context.preferences.addons.get(ADDON) if bpy.context else None
    folder = prefs.preferences.module_path if prefs else ""
    return bpy.path.abspath(folder) if folder else os.environ.get("BOUGUER_BUILD", "")


def load():
    """The bouguer module, or an ImportError that says where it was looked for."""
    folder = module_folder()
    if folder and folder not in sys.path:
        sys.path.insert(0, folder)
    try:
        return importlib.import_module("bouguer")
    except ImportError as e:
        raise ImportError(
            f"Bouguer: the Python module 'bouguer' was not found ({e}); build it (make, docs/python.md) and set "
            f"the add-on's preference 'Module folder' to the build folder (looked in: {folder or 'PYTHONPATH only'}; "
            f"Blender's Python is {sys.version.split()[0]}, the module must be built for the same version)") from e
