"""The fenestra panels in Render Properties."""

import bpy

from . import catalogue


class FenestraPanel:
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {"FENESTRA"}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES


class RENDER_PT_fenestra_sampling(FenestraPanel, bpy.types.Panel):
    bl_label = "fenestra"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        s = context.scene.fenestra
        layout.prop(s, "integrator")
        col = layout.column(align=True)
        col.prop(s, "samples")
        col.prop(s, "time_limit")
        if catalogue.reads(s.integrator, "path"):
            layout.prop(s, "max_depth")
        if catalogue.reads(s.integrator, "light"):
            layout.prop(s, "light_selection")
        if catalogue.reads(s.integrator, "portals"):
            row = layout.row()
            row.prop(s, "portals")
            layout.operator("fenestra.estimate_portals", icon="LIGHT_AREA")
        if catalogue.reads(s.integrator, "light_paths"):
            layout.prop(s, "light_paths_per_sample")
        layout.prop(s, "seed")
        layout.prop(s, "threads")


class RENDER_PT_fenestra_output(FenestraPanel, bpy.types.Panel):
    bl_label = "Output and Measurement"
    bl_parent_id = "RENDER_PT_fenestra_sampling"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        s = context.scene.fenestra
        layout.prop(s, "snapshot_every")
        layout.prop(s, "denoise")
        row = layout.row()
        row.enabled = s.denoise
        row.prop(s, "denoise_mode")
        layout.prop(s, "denoising_data")
        layout.prop(s, "variance_pass")
        layout.prop(s, "reference")
        row = layout.row()
        row.enabled = bool(s.last_report)
        row.operator("fenestra.open_report", icon="URL")
        layout.prop(s, "keep_files")


register, unregister = bpy.utils.register_classes_factory(
    (RENDER_PT_fenestra_sampling, RENDER_PT_fenestra_output)
)
