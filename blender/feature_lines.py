"""Object ‣ Feature Lines: the ridges, valleys or Morse lines of the active mesh
object as Grease Pencil or curves, parented to it."""

import bpy

from .evaluated import unit_in_local
from .job import LinesJob
from .line_objects import replace_lines
from .options import LineOptions
from .tracing import FAILURES, Cancelled, Problem


class OBJECT_OT_crestline_feature_lines(LineOptions, bpy.types.Operator):
    """Draw the feature lines of the active mesh object (as evaluated, modifiers
    applied) as a new object parented to it; running it again replaces them"""

    bl_idname = "object.crestline_feature_lines"
    bl_label = "Feature Lines"
    bl_options = {"REGISTER", "UNDO"}

    output: bpy.props.EnumProperty(
        name="Output",
        items=[
            ("GREASE_PENCIL", "Grease Pencil", "A Grease Pencil object with a layer per family"),
            ("CURVE", "Curve", "Poly splines with a bevel, rendered by Cycles and EEVEE"),
        ],
        default="GREASE_PENCIL",
    )
    width: bpy.props.FloatProperty(
        name="Width",
        description="The lines' thickness, as a share of the mesh's bounding box diagonal",
        default=0.002,
        min=0.0,
        soft_max=0.05,
        precision=4,
        subtype="FACTOR",
    )
    frame_start: bpy.props.IntProperty(
        name="Bake Start", description="First frame of a bake (a bake when the end is after the start)", default=0
    )
    frame_end: bpy.props.IntProperty(
        name="Bake End",
        description="Last frame of a bake: a Grease Pencil keyframe per frame; at or before the start, the current frame only",
        default=0,
    )

    @classmethod
    def poll(cls, context):
        return context.active_object is not None and context.mode == "OBJECT"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        self.draw_line_options(layout)
        layout.prop(self, "output")
        layout.prop(self, "width")
        column = layout.column(align=True)
        column.prop(self, "frame_start")
        column.prop(self, "frame_end")

    def frames(self, context):
        """The frames to trace: the bake's, or the current one."""
        if self.frame_end > self.frame_start:
            return range(self.frame_start, self.frame_end + 1)
        return [context.scene.frame_current]

    def job(self, context):
        """The job of these options on the active object. Raises :class:`Problem`."""
        obj = context.active_object
        frames = self.frames(context)
        if len(frames) > 1 and self.output != "GREASE_PENCIL":
            raise Problem("a bake over frames makes Grease Pencil keyframes: choose the Grease Pencil output")
        return LinesJob(obj, self.tracing(unit=unit_in_local(obj)), frames)

    def execute(self, context):
        current = context.scene.frame_current
        try:
            job = self.job(context)
            for frame in job.frames:
                job.run(context, frame)
        except FAILURES as error:
            return self.failed(error)
        finally:
            restore_frame(context, current)
        return self.finish(context, job)

    def invoke(self, context, event):
        if bpy.app.background or context.window is None:
            return self.execute(context)
        self._current = context.scene.frame_current
        try:
            self._job = self.job(context)
            self._job.start(context, self._job.frames[0])
        except FAILURES as error:
            restore_frame(context, self._current)
            return self.failed(error)
        manager = context.window_manager
        self._timer = manager.event_timer_add(0.1, window=context.window)
        manager.progress_begin(0, len(self._job.frames))
        manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        job = self._job
        if event.type == "ESC":
            job.cancel.set()
        if event.type != "TIMER":
            return {"RUNNING_MODAL"} if event.type == "ESC" else {"PASS_THROUGH"}
        if job.running():
            done = len(job.results)
            context.workspace.status_text_set(
                f"crestline: {job.stage} (frame {done + 1} of {len(job.frames)}); Esc to cancel"
            )
            context.window_manager.progress_update(done)
            return {"RUNNING_MODAL"}
        following = None if job.error else job.next_frame()
        if following is not None:
            try:
                job.start(context, following)
                return {"RUNNING_MODAL"}
            except FAILURES as error:
                job.error = error
        self.stop_modal(context)
        if job.error is not None:
            return self.failed(job.error)
        return self.finish(context, job)

    def stop_modal(self, context):
        """Remove the timer, the progress and the status text; back to the frame."""
        manager = context.window_manager
        manager.event_timer_remove(self._timer)
        manager.progress_end()
        context.workspace.status_text_set(None)
        restore_frame(context, self._current)

    def finish(self, context, job):
        """Make the lines' object from the job's results."""
        obj = replace_lines(context, job.obj, job.results, self.output, 0.5 * self.width * job.diagonal)
        counts = {}
        for lines in job.results.values():
            for kind, n in lines.kinds().items():
                counts[kind] = counts.get(kind, 0) + n
        for warning in job.warnings:
            self.report({"WARNING"}, f"Feature lines: {warning}")
        found = ", ".join(f"{n} {kind}" for kind, n in sorted(counts.items())) or "no lines"
        self.report({"INFO"}, f"{obj.name}: {found}")
        return {"FINISHED"}

    def failed(self, error):
        """Report why the lines could not be made."""
        if isinstance(error, Cancelled):
            self.report({"WARNING"}, "Feature lines cancelled")
        else:
            self.report({"ERROR"}, f"Feature lines: {error}")
        return {"CANCELLED"}


def restore_frame(context, frame):
    """Move the scene back to ``frame`` if a bake moved it."""
    if context.scene.frame_current != frame:
        context.scene.frame_set(frame)
