"""Bouguer inside Blender: a render engine (id BOUGUER) that translates the evaluated depsgraph into a
Bouguer scene description (the JSON schema of docs/scene-format.md, as a dict) and renders it in-process
through the `bouguer` Python module. docs/blender.md says how to install it and what is translated.

The engine only drives (engine.py); export/ holds plain functions from the depsgraph to the scene dict,
testable without the UI; properties.py and ui.py are the settings and their panels."""

bl_info = {
    "name": "Bouguer",
    "author": "Bouguer contributors",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Render > Render Engine > Bouguer",
    "description": "Spectral rendering of transparent, absorbing and scattering matter",
    "doc_url": "https://example.invalid/bouguer/docs/blender.md",
    "category": "Render",
}

if "bpy" in locals():  # a reload from Blender's add-on list
    import importlib
    from . import properties, engine, ui
    importlib.reload(properties)
    importlib.reload(engine)
    importlib.reload(ui)
else:
    from . import properties, engine, ui

import bpy  # noqa: F401  (its presence in locals() marks a reload, above)


def register():
    properties.register()
    engine.register()
    ui.register()


def unregister():
    ui.unregister()
    engine.unregister()
    properties.unregister()
