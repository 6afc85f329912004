"""A Blender camera as crestline's drawing camera, and the map from crestline's
canvas onto the Blender render's pixels.

crestline draws in perspective from an eye with a field of view across the shorter
side of the canvas, the optical axis at its centre; in orthographic projection it
takes the direction only and frames the mesh itself (5% margins). Blender's camera
adds a sensor fit, an orthographic scale and a lens shift: the drawing is made with
the same eye and field of view, and its coordinates are then scaled and moved onto
the render's pixels (:meth:`CameraView.canvas_map`)."""

import math
from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np

from .tracing import Problem

MARGIN = 0.05
"""The share of crestline's canvas left empty on each side when it frames an
orthographic drawing."""


@dataclass(frozen=True)
class CameraView:
    """The scene camera's view: the render's size in pixels, the camera's frame
    (eye and unit right, up and forward vectors, in world coordinates), its field
    of view across the shorter side (perspective) or pixels per unit
    (orthographic), and how far the lens shift moves the picture, in pixels (x right, y down;
    Blender shifts the frame by a share of the side the sensor spans, the
    picture the other way)."""

    width: int
    height: int
    eye: np.ndarray
    right: np.ndarray
    up: np.ndarray
    forward: np.ndarray
    fov: Optional[float]
    pixels_per_unit: Optional[float]
    shift: Tuple[float, float]

    def draw_options(self):
        """The keyword arguments of ``crestline.draw`` for this view."""
        target = self.eye + self.forward
        return dict(
            camera=[*map(float, self.eye), *map(float, target), *map(float, self.up)],
            perspective=self.fov,
            size=(self.width, self.height),
        )

    def canvas_map(self, vertices):
        """``(k, a, b)``: crestline's canvas point (x, y) of a drawing of
        ``vertices`` (world coordinates, as drawn) is the render's pixel
        (k x + a, k y + b)."""
        dx, dy = self.shift
        if self.fov is not None:
            return 1.0, dx, dy
        low, high = vertices.min(axis=0), vertices.max(axis=0)
        center = 0.5 * (low + high)
        across = (vertices - center) @ np.column_stack([self.right, self.up])
        extent = across.max(axis=0) - across.min(axis=0)
        usable = 1.0 - 2.0 * MARGIN
        scale = min(usable * self.width / extent[0], usable * self.height / extent[1])
        middle = 0.5 * (across.max(axis=0) + across.min(axis=0))
        offset = center - self.eye
        p = self.pixels_per_unit
        k = p / scale
        a = 0.5 * self.width * (1 - k) + p * (middle[0] + offset @ self.right) + dx
        b = 0.5 * self.height * (1 - k) - p * (middle[1] + offset @ self.up) + dy
        return k, a, b


def render_size(scene):
    """The render's width and height in pixels (resolution and percentage)."""
    render = scene.render
    return (
        int(render.resolution_x * render.resolution_percentage / 100),
        int(render.resolution_y * render.resolution_percentage / 100),
    )


def camera_view(scene):
    """The :class:`CameraView` of ``scene``'s camera. Raises :class:`Problem`
    without a camera, for a panoramic one or non-square pixels."""
    camera = scene.camera
    if camera is None or camera.type != "CAMERA":
        raise Problem("the scene has no camera")
    data = camera.data
    if data.type not in ("PERSP", "ORTHO"):
        raise Problem(f"the camera '{camera.name}' is {data.type.lower()}: only perspective and orthographic cameras are drawn")
    if scene.render.pixel_aspect_x != scene.render.pixel_aspect_y:
        raise Problem("the render's pixels are not square (pixel aspect): crestline draws on square pixels")
    width, height = render_size(scene)
    fit_px, sensor = sensor_fit(data, width, height)
    matrix = np.array(camera.matrix_world, dtype=np.float64)
    axes = matrix[:3, :3] / np.linalg.norm(matrix[:3, :3], axis=0)
    perspective = data.type == "PERSP"
    focal_px = data.lens / sensor * fit_px
    return CameraView(
        width=width,
        height=height,
        eye=matrix[:3, 3],
        right=axes[:, 0],
        up=axes[:, 1],
        forward=-axes[:, 2],
        fov=math.degrees(2 * math.atan(0.5 * min(width, height) / focal_px)) if perspective else None,
        pixels_per_unit=None if perspective else fit_px / data.ortho_scale,
        shift=(-data.shift_x * fit_px, data.shift_y * fit_px),
    )


def sensor_fit(data, width, height):
    """The render's side (pixels) the camera's sensor spans, and the sensor's size
    (mm) along it, as Blender fits the sensor to the render."""
    fit = data.sensor_fit
    if fit == "AUTO":
        return max(width, height), data.sensor_width
    if fit == "HORIZONTAL":
        return width, data.sensor_width
    return height, data.sensor_height
