"""The Bouguer panels: Render properties (integrator, spectral mode, samples or time, seed, depth,
threads, optional outputs) and Material properties (the Blender material as it is, or a library
medium or a material file, its index, and a priority for nested media)."""
import bpy


class BouguerPanel:
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    COMPAT_ENGINES = {"BOUGUER"}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES


class BOUGUER_PT_render(BouguerPanel, bpy.types.Panel):
    bl_label = "Bouguer"
    bl_context = "render"

    def draw(self, context):
        s = context.scene.bouguer
        layout = self.layout
        layout.use_property_split = True
        layout.prop(s, "integrator")
        layout.prop(s, "spectral")
        layout.prop(s, "use_time")
        layout.prop(s, "time_s" if s.use_time else "spp")
        layout.prop(s, "use_denoise")
        layout.prop(s, "seed")
        layout.prop(s, "max_depth")
        layout.prop(s, "threads")
        col = layout.column(heading="Also Write")
        col.prop(s, "spectral_exr")
        col.prop(s, "stats_json")


class BOUGUER_PT_material(BouguerPanel, bpy.types.Panel):
    bl_label = "Bouguer"
    bl_context = "material"

    @classmethod
    def poll(cls, context):
        return super().poll(context) and context.material is not None

    def draw(self, context):
        m = context.material.bouguer
        layout = self.layout
        layout.use_property_split = True
        layout.prop(m, "source")
        if m.source == "LIBRARY":
            layout.prop(m, "library")  # searches bouguer.material_names()
        elif m.source == "FILE":
            layout.prop(m, "file")
        if m.source != "BLENDER":
            layout.prop(m, "concentration")
            layout.prop(m, "ior_source")
            if m.ior_source in ("NUMBER", "ABBE"):
                layout.prop(m, "ior")
            if m.ior_source == "ABBE":
                layout.prop(m, "abbe")
            if m.ior_source == "SELLMEIER":
                layout.prop(m, "sellmeier")
        layout.prop(m, "use_priority")
        if m.use_priority:
            layout.prop(m, "priority")


CLASSES = (BOUGUER_PT_render, BOUGUER_PT_material)


def register():
    for c in CLASSES:
        bpy.utils.register_class(c)


def unregister():
    for c in reversed(CLASSES):
        bpy.utils.unregister_class(c)
