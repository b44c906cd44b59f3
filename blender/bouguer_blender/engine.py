"""The render engine: it only drives. export/ translates the evaluated depsgraph into the scene dict,
the bouguer module renders it in-process, pass by pass, into Blender's render result."""
import json
import os
import traceback

import bpy
import numpy as np

from . import module
from .export import export_scene

# The reports and statistics of the last render (tests read them; Blender's report and status line
# show them to the user).
last_reports = []
last_stats = {}


def rgba_rows(rgb):
    """Bouguer's (H, W, 3), row 0 at the top, as Blender's pass rect: (H*W, 4), row 0 at the bottom."""
    h, w, _ = rgb.shape
    out = np.ones((h, w, 4), dtype=np.float32)
    out[..., :3] = rgb[::-1]
    return out.reshape(-1, 4)


class BouguerRenderEngine(bpy.types.RenderEngine):
    bl_idname = "BOUGUER"
    bl_label = "Bouguer"
    bl_use_preview = False
    bl_use_postprocess = True
    bl_use_shading_nodes_custom = False  # Blender's own shader nodes, as Cycles uses them

    def stop_requested(self):
        """Esc in Blender's render window (the one place the engine asks; tests put a stub here)."""
        return self.test_break()

    def report_all(self, warnings):
        last_reports[:] = warnings
        for w in warnings:
            self.report({"WARNING"}, w)

    def render(self, depsgraph):
        try:
            bouguer = module.load()
        except ImportError as e:
            last_reports[:] = [str(e)]
            self.report({"ERROR"}, str(e))
            return
        scene = depsgraph.scene
        settings = scene.bouguer
        try:
            exported = export_scene(depsgraph, bouguer, settings)
        except Exception as e:  # a Blender datablock the translation did not foresee: say so, no traceback dialog
            traceback.print_exc()
            last_reports[:] = [f"Bouguer: the scene could not be translated ({type(e).__name__}: {e}); please report it"]
            self.report({"ERROR"}, last_reports[0])
            return
        self.report_all(exported.reports.warnings)
        width, height = exported.scene["camera"]["resolution"]
        base = os.path.dirname(bpy.data.filepath) or os.getcwd()  # an unsaved file has no folder
        try:
            loaded = bouguer.load_dict(exported.scene, base=base, meshes=exported.meshes)
        except bouguer.Error as e:
            last_reports.append(str(e))
            self.report({"ERROR"}, f"Bouguer: {e}")
            return
        result = self.begin_result(0, 0, width, height)
        combined = result.layers[0].passes["Combined"]

        def on_pass(rgb, done, spp):
            combined.rect = rgba_rows(rgb)
            self.update_result(result)
            stats = loaded.stats
            of = "" if settings.use_time else f"/{spp}"
            self.update_stats("", f"Bouguer: {done}{of} samples, {stats['rays_per_second'] / 1e6:.2f} M rays/s")

        kwargs = {}
        if settings.use_time:
            kwargs["time_s"] = settings.time_s
        else:
            kwargs["spp"] = settings.spp
        if settings.spectral_exr:
            kwargs["spectral_exr"] = bpy.path.abspath(settings.spectral_exr)
        if settings.use_denoise:
            kwargs["denoise"] = True  # the last image only; the passes before show the noisy image so far
        try:
            rgb = bouguer.render(loaded, threads=settings.threads, on_pass=on_pass, should_stop=self.stop_requested,
                                 progress=self.update_progress, **kwargs)
        except bouguer.Error as e:
            self.report({"ERROR"}, f"Bouguer: {e}")
            self.end_result(result)
            return
        combined.rect = rgba_rows(rgb)
        self.end_result(result)
        stats = loaded.stats
        last_stats.clear()
        last_stats.update(stats)
        self.update_stats("", f"Bouguer: {stats['spp']} samples in {stats['seconds']:.1f} s, "
                              f"{stats['rays_per_second'] / 1e6:.2f} M rays/s" + (" (stopped)" if stats["stopped"] else ""))
        if settings.stats_json:
            write_stats(bpy.path.abspath(settings.stats_json), stats, settings, width, height)


def write_stats(path, stats, settings, width, height):
    # "integrator": the estimator that rendered (Automatic's choice), as the command line's stats say.
    data = dict(stats, resolution=[width, height], integrator=stats.get("integrator") or settings.integrator,
                spectral=settings.spectral, threads=settings.threads)
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(data, f, indent=2)
        f.write("\n")
    os.replace(tmp, path)


# Blender's own panels that show for Bouguer too (the material's node inputs, the world, lights,
# output and dimensions), as third-party engines register themselves with them.
def compatible_panels():
    keep = {"RENDER_PT_format", "RENDER_PT_frame_range", "RENDER_PT_output", "RENDER_PT_encoding",
            "RENDER_PT_dimensions", "RENDER_PT_stamp", "RENDER_PT_color_management", "RENDER_PT_post_processing",
            "DATA_PT_light", "DATA_PT_lens", "DATA_PT_camera", "DATA_PT_camera_display",
            "EEVEE_MATERIAL_PT_surface", "EEVEE_MATERIAL_PT_volume", "EEVEE_WORLD_PT_surface",
            "MATERIAL_PT_preview", "DATA_PT_EEVEE_light", "DATA_PT_EEVEE_light_distance"}
    for name in dir(bpy.types):
        panel = getattr(bpy.types, name)
        if name in keep and hasattr(panel, "COMPAT_ENGINES"):
            yield panel


def register():
    bpy.utils.register_class(BouguerRenderEngine)
    for panel in compatible_panels():
        panel.COMPAT_ENGINES.add(BouguerRenderEngine.bl_idname)


def unregister():
    for panel in compatible_panels():
        panel.COMPAT_ENGINES.discard(BouguerRenderEngine.bl_idname)
    bpy.utils.unregister_class(BouguerRenderEngine)
