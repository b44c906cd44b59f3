"""The add-on's settings: scene.bouguer (the Render panel), material.bouguer (the Material panel) and
the preferences (where the module is)."""
import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

# The library's dispersion formulas (docs/scene-format.md, media.ior).
SELLMEIER = ["N-BK7", "F2", "N-SF11", "fused-silica", "water", "diamond"]


class BouguerPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    module_path: StringProperty(
        name="Module folder", subtype="DIR_PATH",
        description="The folder with the bouguer Python module (the build folder, build/bouguer.cpython-*.so); "
                    "empty: BOUGUER_BUILD or PYTHONPATH")

    def draw(self, context):
        self.layout.prop(self, "module_path")


class BouguerRenderSettings(bpy.types.PropertyGroup):
    integrator: EnumProperty(
        name="Integrator", default="path",
        items=[("path", "Path", "Unbiased path tracing"),
               ("auto", "Automatic", "Short trials of path, bidirectional and VCM choose the one with the least "
                                     "noise for its cost (docs/rendering.md)"),
               ("whitted", "Whitted", "The paper's ray tracer: specular paths and direct light"),
               ("light", "Light", "Light tracing: caustics on diffuse surfaces"),
               ("bdpt", "Bidirectional", "Bidirectional path tracing: light through glass, lamps inside media"),
               ("vcm", "VCM", "Vertex connection and merging: caustics seen through glass")])
    spectral: EnumProperty(
        name="Spectral", default="hero",
        items=[("full", "Full", "96 bins, 360-830 nm"),
               ("hero", "Hero", "4 wavelengths sampled per path"),
               ("rgb3", "RGB (3 lines)", "The paper's 700.0/546.1/435.8 nm RGB")])
    use_time: BoolProperty(name="Time Budget", default=False,
                           description="Render for a number of seconds instead of a number of samples")
    spp: IntProperty(name="Samples", default=64, min=1, max=1 << 20, description="Samples per pixel")
    time_s: FloatProperty(name="Seconds", default=30.0, min=0.1, max=1e6, description="Seconds of rendering")
    use_denoise: BoolProperty(name="Denoise", default=False,
                              description="Filter the image from its two half buffers (non-local means): smooth "
                                          "noise goes, edges stay; biased, so not for measurements "
                                          "(docs/rendering.md)")
    seed: IntProperty(name="Seed", default=0, min=0, description="The same seed gives the same image")
    max_depth: IntProperty(name="Max Depth", default=32, min=1, max=100000,
                           description="Deepest path: surface vertices")
    threads: IntProperty(name="Threads", default=0, min=0, max=1024, description="0: all cores")
    spectral_exr: StringProperty(name="Spectral EXR", subtype="FILE_PATH",
                                 description="Also write the render's spectra (needs Spectral: Full)")
    stats_json: StringProperty(name="Statistics JSON", subtype="FILE_PATH",
                               description="Also write seconds, rays, rays per second and samples as JSON")


def library_names(self, context, edit_text):
    """The library's names for the Medium field's search (bouguer.material_names())."""
    from . import module
    try:
        names = module.load().material_names()
    except ImportError:
        return []
    return [n for n in names if edit_text.lower() in n.lower()]


class BouguerMaterialSettings(bpy.types.PropertyGroup):
    source: EnumProperty(
        name="Source", default="BLENDER",
        items=[("BLENDER", "Blender Material", "Translate the material's nodes (docs/blender.md)"),
               ("LIBRARY", "Library Medium", "A measured medium of Bouguer's library inside the object"),
               ("FILE", "Material File", "A material CSV inside the object (docs/materials.md)")])
    library: StringProperty(name="Medium", default="red-glass", search=library_names,
                            description="A name of the library (bouguer material list)")
    concentration: FloatProperty(name="Concentration", default=1.0, min=0.0, max=1e6,
                                 description="mol/L for a molar solute, otherwise a factor on the absorption")
    file: StringProperty(name="File", subtype="FILE_PATH", description="A material CSV")
    ior_source: EnumProperty(
        name="Index", default="DEFAULT",
        items=[("DEFAULT", "Medium's Own", "The library entry's or the file's own index"),
               ("NUMBER", "Constant", "One index at all wavelengths"),
               ("ABBE", "Abbe Number", "n = A + B/λ² through n_d with the Abbe number V_d"),
               ("SELLMEIER", "Sellmeier", "A dispersion formula of the library")])
    ior: FloatProperty(name="IOR (n_d)", default=1.5, min=1.0, max=5.0)
    abbe: FloatProperty(name="Abbe Number", default=64.2, min=5.0, max=200.0)
    sellmeier: EnumProperty(name="Glass", items=[(n, n, "") for n in SELLMEIER], default="N-BK7")
    use_priority: BoolProperty(name="Priority", default=False,
                               description="Nested media: where objects with a priority overlap, the highest fills")
    priority: IntProperty(name="Priority", default=1, min=0, max=1000000)


CLASSES = (BouguerPreferences, BouguerRenderSettings, BouguerMaterialSettings)


def register():
    for c in CLASSES:
        bpy.utils.register_class(c)
    bpy.types.Scene.bouguer = PointerProperty(type=BouguerRenderSettings)
    bpy.types.Material.bouguer = PointerProperty(type=BouguerMaterialSettings)


def unregister():
    del bpy.types.Material.bouguer
    del bpy.types.Scene.bouguer
    for c in reversed(CLASSES):
        bpy.utils.unregister_class(c)
