"""The render engine "fenestra": F12 exports the scene, runs fenestra with the panel's
settings and shows its snapshots in the Render window as the image refines; Esc stops
fenestra as Ctrl-C does and keeps the image so far."""

import os
import shlex
import shutil
import tempfile
import time

import bpy
import numpy as np

from . import export, mainthread, preferences, run

# Seconds between looks at fenestra's progress and snapshots.
POLL_S = 0.05


class FenestraRenderEngine(bpy.types.RenderEngine):
    bl_idname = "FENESTRA"
    bl_label = "fenestra"
    bl_use_preview = False
    bl_use_postprocess = True

    def update_render_passes(self, scene=None, renderlayer=None):
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", "COLOR")
        for name, channels, kind in extra_passes(scene.fenestra if scene else None):
            self.register_pass(scene, renderlayer, name, 3, channels, kind)

    def render(self, depsgraph):
        scene = depsgraph.scene
        keep = kept_folder(scene)
        folder = None
        # Everything inside the try: an exception escaping render() crashes Blender.
        try:
            if keep:
                try:
                    os.makedirs(keep, exist_ok=True)
                except OSError as e:
                    raise RuntimeError(f"cannot make the Keep Files folder {keep}: {e}") from e
            folder = keep or tempfile.mkdtemp(prefix="fenestra-")
            self._render(scene, depsgraph.view_layer, folder)
        except Exception as e:
            self.report({"ERROR"}, f"fenestra: {e}")
        finally:
            if folder and not keep:
                shutil.rmtree(folder, ignore_errors=True)

    def _render(self, scene, view_layer, folder):
        settings = scene.fenestra
        binary = preferences.binary(bpy.context)
        self.update_stats("", "fenestra: exporting the scene (glTF)")
        exported = export.export(scene, view_layer, folder, give_up=self.test_break)
        for note in exported.notes:
            self.report({"WARNING"}, f"fenestra: {note}")
        output = os.path.join(folder, "render.exr")
        # A kept folder's last render goes (the folder is the add-on's own): its sidecar
        # saying "complete" would send this render's snapshots beside it (fenestra never
        # overwrites a complete render with a partial one), where the Render window does
        # not look.
        for name in os.listdir(folder):
            if name.startswith("render."):
                os.remove(os.path.join(folder, name))
        command = export.render_command(binary, exported, settings, output)
        with open(os.path.join(folder, "command.txt"), "w") as f:
            f.write(shlex.join(command) + "\n")
        fenestra = run.Fenestra(command, os.path.join(folder, "fenestra.log"))
        for name, channels, _ in extra_passes(settings):
            self.add_pass(name, 3, channels)
        result = self.begin_result(0, 0, exported.width, exported.height)
        try:
            stopped, reported = self._watch(fenestra, result, output, settings)
        except BaseException:
            fenestra.kill()
            raise
        code, stdout, log = fenestra.wait()
        self._report_warnings(fenestra, reported)
        final = self._final_image(output)
        # Stopped by Esc, fenestra exits as after Ctrl-C (130) with the image so far written.
        if final is None or (code != 0 and not stopped):
            self.end_result(result)
            detail = "\n".join(log[-5:]) or f"exit code {code}"
            raise RuntimeError(f"fenestra failed: {detail}")
        loaded = self._load_final(result, final, settings)
        self.end_result(result)
        if not loaded:
            return
        summary = stdout.strip().splitlines()
        self.update_stats("", f"fenestra: {summary[0]}" if summary else "fenestra: done")
        if settings.reference:
            from . import report  # only for renders measured against a reference

            path = report.write(
                binary,
                self._report_folder(scene, folder),
                final,
                bpy.path.abspath(settings.reference),
            )
            # The evaluated scene is a copy: the button reads the original's.
            mainthread.call(
                setattr,
                scene.original.fenestra,
                "last_report",
                path,
                give_up=mainthread.deadline(5.0),
            )

    @staticmethod
    def _report_folder(scene, folder):
        """Where a render's report goes: beside the kept files, else a folder that outlives
        the render's temporary one."""
        if scene.fenestra.keep_files:
            return folder
        return tempfile.mkdtemp(prefix="fenestra-report-")

    def _watch(self, fenestra, result, output, settings):
        """Follows fenestra until it exits: progress and ETA, warnings, snapshots (denoised
        ones with Denoise) into the render result; Esc stops it. Returns whether it was
        stopped and the warnings shown."""
        integrator, time_limit = settings.integrator, settings.time_limit
        shown_path = denoised_path(output) if settings.denoise else output
        shown, reported, stopped = 0.0, 0, False
        while fenestra.running():
            time.sleep(POLL_S)
            if not stopped and self.stop_requested():
                fenestra.stop()
                stopped = True
                self.update_stats("", "fenestra: stopping, keeping the image so far")
            reported = self._report_warnings(fenestra, reported)
            if not stopped:
                f, left = run.fraction(fenestra.snapshot(), time_limit)
                self.update_progress(f)
                eta = f", {left:.0f} s left" if left is not None else ""
                self.update_stats("", f"fenestra {integrator}: {100 * f:.0f}%{eta}")
                shown = self._show_snapshot(result, shown_path, shown)
        return stopped, reported

    def _report_warnings(self, fenestra, reported):
        """Reports fenestra's warnings after the first `reported`; how many there are."""
        warnings = fenestra.snapshot().warnings
        for w in warnings[reported:]:
            self.report({"WARNING"}, f"fenestra: {w}")
        return len(warnings)

    def _load_final(self, result, final, settings):
        """fenestra's final image (denoised with Denoise, the raw one then the Noisy Image
        pass), its variance and features into the render result; False if Blender is
        quitting: it stops the render and then waits for it on the main thread, which then
        loads no image (after a few seconds the image is left on disk)."""
        give_up = mainthread.deadline(5.0)
        stem = final[: -len(".exr")]
        combined = denoised_path(final) if settings.denoise else final
        passes = result.layers[0].passes
        try:
            pixels = mainthread.call(read_pixels, combined, give_up=give_up)
            passes.find_by_name("Combined", "").rect = pixels
            for name, _, _ in extra_passes(settings):
                path = stem + PASS_FILES[name]
                image = mainthread.call(read_pixels, path, give_up=give_up)
                passes.find_by_name(name, "").rect = image[:, :3]
        except mainthread.Abandoned:
            return False
        return True

    def stop_requested(self):
        """Whether the user pressed Esc (the one place that asks Blender)."""
        return self.test_break()

    def _show_snapshot(self, result, output, shown):
        """Shows fenestra's latest snapshot if it is newer than `shown` (its mtime)."""
        try:
            mtime = os.stat(output).st_mtime
        except FileNotFoundError:
            return shown
        if mtime <= shown:
            return shown
        try:
            pixels = mainthread.call(read_pixels, output, give_up=self.test_break)
        except mainthread.Abandoned:
            return shown
        result.layers[0].passes.find_by_name("Combined", "").rect = pixels
        self.update_result(result)
        return mtime

    @staticmethod
    def _interrupted(output):
        return output[: -len(".exr")] + ".interrupted.exr"

    @staticmethod
    def _final_image(output):
        """fenestra's image: OUT.exr, or beside it when an interruption must not replace a
        complete render there (OUT.interrupted.exr)."""
        for path in (FenestraRenderEngine._interrupted(output), output):
            if os.path.exists(path):
                return path
        return None


# Each extra pass's file beside fenestra's OUT.exr (its suffix in place of ".exr").
PASS_FILES = {
    "Noisy Image": ".exr",
    "Denoising Albedo": ".albedo.exr",
    "Denoising Normal": ".normal.exr",
    "Variance": ".var.exr",
}


def extra_passes(settings):
    """The passes besides Combined that `settings` ask for: (name, channels, kind)."""
    if settings is None:
        return []
    passes = []
    if settings.denoise:
        passes.append(("Noisy Image", "RGB", "COLOR"))
    if settings.denoise or settings.denoising_data:
        passes += [("Denoising Albedo", "RGB", "COLOR"), ("Denoising Normal", "XYZ", "VECTOR")]
    if settings.variance_pass:
        passes.append(("Variance", "RGB", "COLOR"))
    return passes


def denoised_path(output):
    """fenestra's denoised image beside OUT.exr: OUT.denoised.exr."""
    return output[: -len(".exr")] + ".denoised.exr"


def kept_folder(scene):
    """Where Keep Files keeps a scene's render: a folder of the add-on's own inside the one
    chosen ("fenestra-SCENE"), which it may clear: the user's own files beside it are never
    touched. None without Keep Files."""
    keep = scene.fenestra.keep_files
    if not keep:
        return None
    return os.path.join(bpy.path.abspath(keep), f"fenestra-{bpy.path.clean_name(scene.name)}")


def read_pixels(path):
    """An image's float RGBA pixels, rows bottom up as render passes hold them (main
    thread: it goes through bpy.data.images)."""
    image = bpy.data.images.load(path, check_existing=False)
    try:
        w, h = image.size
        pixels = np.empty(w * h * 4, dtype=np.float32)
        image.pixels.foreach_get(pixels)
        return pixels.reshape(-1, 4)
    finally:
        bpy.data.images.remove(image)


def compatible_panels():
    """Cycles' panels that describe what fenestra reads too (camera, lights, world, materials)."""
    wanted = (
        "DATA_PT_lens",
        "DATA_PT_camera",
        "DATA_PT_camera_dof",
        "DATA_PT_light",
        "DATA_PT_EEVEE_light",
        "DATA_PT_area",
        "DATA_PT_spot",
        "WORLD_PT_context_world",
        "EEVEE_MATERIAL_PT_surface",
        "MATERIAL_PT_preview",
        "RENDER_PT_format",
        "RENDER_PT_dimensions",
        "RENDER_PT_color_management",
    )
    for name in wanted:
        panel = getattr(bpy.types, name, None)
        if panel is not None and hasattr(panel, "COMPAT_ENGINES"):
            yield panel


def register():
    bpy.utils.register_class(FenestraRenderEngine)
    for panel in compatible_panels():
        panel.COMPAT_ENGINES.add(FenestraRenderEngine.bl_idname)


def unregister():
    for panel in compatible_panels():
        panel.COMPAT_ENGINES.discard(FenestraRenderEngine.bl_idname)
    bpy.utils.unregister_class(FenestraRenderEngine)
