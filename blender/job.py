"""Tracing the lines of one object over one or more frames, in the caller's
thread or in a worker thread that Escape can stop between two stages."""

import threading
import warnings

import numpy as np

from .evaluated import mesh_arrays
from .tracing import Cancelled, trace


class LinesJob:
    """The lines of ``obj`` at each of ``frames`` (``{frame: crestline.Lines}`` in
    :attr:`results`), traced with ``options`` (:class:`tracing.Tracing`).
    The mesh is read in the main thread, from the context of the call (Blender's
    data is not thread-safe, and a context is not kept); the library's computation
    may run in a worker thread."""

    def __init__(self, obj, options, frames):
        self.obj = obj
        self.options = options
        self.frames = list(frames)
        self.results = {}
        self.diagonal = 0.0
        self.stage = ""
        self.warnings = []
        self.error = None
        self.cancel = threading.Event()
        self._thread = None

    def progress(self, stage, seconds):
        """The library's progress callback: notes the stage, stops if cancelled."""
        if self.cancel.is_set():
            raise Cancelled(stage)
        if seconds is None:
            self.stage = stage

    def arrays(self, context, frame):
        """The evaluated mesh at ``frame`` (the scene is moved there when baking)."""
        scene = context.scene
        if len(self.frames) > 1 and scene.frame_current != frame:
            scene.frame_set(frame)
        vertices, faces = mesh_arrays(self.obj, context.evaluated_depsgraph_get())
        size = float(np.linalg.norm(vertices.max(axis=0) - vertices.min(axis=0)))
        self.diagonal = max(self.diagonal, size)
        return vertices, faces

    def run(self, context, frame):
        """Trace the lines at ``frame`` in this thread. Raises :class:`Problem`,
        :class:`Cancelled` or the library's errors."""
        vertices, faces = self.arrays(context, frame)
        self.traced(frame, vertices, faces)

    def traced(self, frame, vertices, faces):
        """Trace the lines of the arrays, keeping the library's warnings about the
        input (repaired samples, no line found) in :attr:`warnings`."""
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            self.results[frame] = trace(vertices, faces, self.options, self.progress)
        for warning in caught:
            text = f"frame {frame}: {warning.message}" if len(self.frames) > 1 else str(warning.message)
            if text not in self.warnings:
                self.warnings.append(text)

    def start(self, context, frame):
        """Trace the lines at ``frame`` in a worker thread; :attr:`error` holds
        what it raised once :meth:`running` is False."""
        vertices, faces = self.arrays(context, frame)

        def work():
            try:
                self.traced(frame, vertices, faces)
            except Exception as error:  # reported by the operator in the main thread
                self.error = error

        self._thread = threading.Thread(target=work, daemon=True)
        self._thread.start()

    def running(self):
        """Whether the worker thread is still tracing."""
        return self._thread is not None and self._thread.is_alive()

    def next_frame(self):
        """The first frame without lines yet, or None when all are traced."""
        return next((frame for frame in self.frames if frame not in self.results), None)
