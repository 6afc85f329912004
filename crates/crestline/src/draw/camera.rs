//! The camera: where the mesh is seen from, and how points map to the canvas.
//!
//! Canvas coordinates are pixels with the origin at the top-left corner, x to the
//! right and y **down** (as in SVG). Depth is the distance along the viewing
//! direction, in the units of the mesh: larger is farther from the viewer.
//!
//! Viewing directions given as [`View::Orbit`] follow one convention: azimuth 0 and
//! elevation 0 look along −z with +y up (the eye on the +z side). A positive azimuth
//! turns the eye about +y towards +x; a positive elevation raises it towards +y.

use crate::{Error, Point, Result, Vector};

/// Where the camera looks from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum View {
    /// A direction around the mesh, in degrees (see the module docs for the axes);
    /// the camera is placed and the drawing framed automatically.
    Orbit {
        /// Degrees around the vertical axis.
        azimuth: f64,
        /// Degrees above the horizontal plane.
        elevation: f64,
    },
    /// An explicit eye, target and up vector. With a perspective projection they are
    /// used as given; an orthographic projection uses only the direction and frames
    /// the mesh automatically.
    LookAt {
        /// Where the camera is.
        eye: Point,
        /// The point it looks at.
        target: Point,
        /// The direction that is up on the screen.
        up: Vector,
    },
}

impl Default for View {
    fn default() -> Self {
        View::Orbit {
            azimuth: 0.0,
            elevation: 0.0,
        }
    }
}

/// How 3D points are projected onto the canvas.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum Projection {
    /// Parallel projection (the default).
    #[default]
    Orthographic,
    /// Central projection with the field of view `fov` in degrees, across the
    /// shorter side of the canvas.
    Perspective {
        /// Vertical field of view, in degrees.
        fov: f64,
    },
}

/// The largest canvas side, in pixels.
pub const MAX_CANVAS_SIDE: u32 = 20_000;

/// The share of the canvas left empty on each side by automatic framing.
const MARGIN: f64 = 0.05;

/// A point on the canvas with its depth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScreenPoint {
    /// Pixels from the left edge.
    pub x: f64,
    /// Pixels from the top edge.
    pub y: f64,
    /// Distance along the viewing direction (mesh units; larger is farther).
    pub depth: f64,
}

/// A camera with its canvas: built by [`Camera::framing`], it maps mesh points to
/// [`ScreenPoint`]s.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    width: u32,
    height: u32,
    /// The eye (perspective), or the depth origin (orthographic).
    eye: Point,
    forward: Vector,
    right: Vector,
    up: Vector,
    perspective: bool,
    /// Pixels per mesh unit (orthographic) or the focal length in pixels
    /// (perspective).
    scale: f64,
    /// The canvas point of the optical axis, in pixels.
    principal: [f64; 2],
    /// Offset of the drawing on the image plane (orthographic), in mesh units.
    shift: [f64; 2],
    /// Points nearer than this to the eye plane are not projected (perspective).
    near: f64,
}

impl Camera {
    /// A camera looking at `points` (usually the mesh vertices) from `view`, on a
    /// canvas of `width` × `height` pixels. Orthographic cameras, and orbit views in
    /// perspective, frame the points with a margin of 5% on each side.
    ///
    /// Errors ([`Error::Argument`]): a canvas side of 0 or above
    /// [`MAX_CANVAS_SIDE`], a non-finite angle or coordinate, a field of view
    /// outside (0°, 180°), an eye on the target or an up vector along the view; and
    /// ([`Error::Mesh`]) no points or points without extent.
    pub fn framing(
        points: &[Point],
        view: View,
        projection: Projection,
        width: u32,
        height: u32,
    ) -> Result<Camera> {
        check_canvas(width, height)?;
        let fov = match projection {
            Projection::Orthographic => None,
            Projection::Perspective { fov } => Some(check_fov(fov)?),
        };
        let (center, radius) = bounding_sphere(points)?;
        let (direction, up) = match view {
            View::Orbit { azimuth, elevation } => orbit(azimuth, elevation)?,
            View::LookAt { eye, target, up } => look_at(&eye, &target, &up)?,
        };
        let forward = -direction;
        let right = forward.cross(&up).normalize();
        let up = right.cross(&forward);
        let principal = [f64::from(width) / 2.0, f64::from(height) / 2.0];
        let short_side = f64::from(width.min(height));
        let mut camera = Camera {
            width,
            height,
            eye: center,
            forward,
            right,
            up,
            perspective: fov.is_some(),
            scale: 1.0,
            principal,
            shift: [0.0, 0.0],
            near: 1e-3 * radius,
        };
        match (fov, view) {
            (None, _) => camera.fit_orthographic(points)?,
            (Some(fov), View::Orbit { .. }) => {
                let half = (0.5 * fov).to_radians();
                let fitted = (1.0 - 2.0 * MARGIN) * half;
                camera.eye = center + direction * (radius / fitted.sin());
                camera.scale = 0.5 * short_side / half.tan();
            }
            (Some(fov), View::LookAt { eye, .. }) => {
                camera.eye = eye;
                camera.scale = 0.5 * short_side / (0.5 * fov).to_radians().tan();
            }
        }
        Ok(camera)
    }

    /// Scale and shift an orthographic camera so the projected points fill the
    /// canvas up to the margin.
    fn fit_orthographic(&mut self, points: &[Point]) -> Result<()> {
        let mut low = [f64::INFINITY; 2];
        let mut high = [f64::NEG_INFINITY; 2];
        for p in points {
            let v = p - self.eye;
            for (axis, value) in [v.dot(&self.right), v.dot(&self.up)]
                .into_iter()
                .enumerate()
            {
                low[axis] = low[axis].min(value);
                high[axis] = high[axis].max(value);
            }
        }
        let extent = [high[0] - low[0], high[1] - low[1]];
        let usable = 1.0 - 2.0 * MARGIN;
        let fits = [
            usable * f64::from(self.width) / extent[0],
            usable * f64::from(self.height) / extent[1],
        ];
        self.scale = fits[0].min(fits[1]);
        if !(self.scale.is_finite() && self.scale > 0.0) {
            return Err(Error::Mesh(
                "the mesh has no extent across the viewing direction".into(),
            ));
        }
        self.shift = [0.5 * (low[0] + high[0]), 0.5 * (low[1] + high[1])];
        Ok(())
    }

    /// Canvas width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Canvas height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The unit viewing direction (from the eye into the scene).
    #[cfg(test)]
    pub fn forward(&self) -> Vector {
        self.forward
    }

    /// The vector from `p` towards the viewer: to the eye in perspective, against
    /// the viewing direction in orthographic projection. Its sign against a surface
    /// normal tells front from back.
    pub fn toward_viewer(&self, p: &Point) -> Vector {
        if self.perspective {
            self.eye - p
        } else {
            -self.forward
        }
    }

    /// The canvas position and depth of `p`, or `None` for a point behind (or too
    /// near) the eye of a perspective camera.
    pub fn project(&self, p: &Point) -> Option<ScreenPoint> {
        let v = p - self.eye;
        let depth = v.dot(&self.forward);
        let (sx, sy) = if self.perspective {
            if depth <= self.near {
                return None;
            }
            (v.dot(&self.right) / depth, v.dot(&self.up) / depth)
        } else {
            (
                v.dot(&self.right) - self.shift[0],
                v.dot(&self.up) - self.shift[1],
            )
        };
        Some(ScreenPoint {
            x: self.principal[0] + self.scale * sx,
            y: self.principal[1] - self.scale * sy,
            depth,
        })
    }

    /// The depth as a quantity that varies linearly across a projected triangle:
    /// the depth itself in orthographic projection, its reciprocal in perspective.
    pub(crate) fn linear_depth(&self, depth: f64) -> f64 {
        if self.perspective {
            depth.recip()
        } else {
            depth
        }
    }

    /// The inverse of [`Camera::linear_depth`].
    pub(crate) fn depth_from_linear(&self, linear: f64) -> f64 {
        self.linear_depth(linear)
    }
}

fn check_canvas(width: u32, height: u32) -> Result<()> {
    for (name, side) in [("width", width), ("height", height)] {
        if side == 0 || side > MAX_CANVAS_SIDE {
            return Err(Error::Argument(format!(
                "the canvas {name} (`size`) must be between 1 and {MAX_CANVAS_SIDE} pixels, got {side}"
            )));
        }
    }
    Ok(())
}

fn check_fov(fov: f64) -> Result<f64> {
    if fov.is_finite() && fov > 0.0 && fov < 180.0 {
        Ok(fov)
    } else {
        Err(Error::Argument(format!(
            "the field of view (`perspective`) must be strictly between 0 and 180 degrees, got {fov}"
        )))
    }
}

/// The centre of the bounding box and the largest distance of a point from it.
fn bounding_sphere(points: &[Point]) -> Result<(Point, f64)> {
    let first = points
        .first()
        .ok_or_else(|| Error::Mesh("nothing to draw: the mesh has no vertices".into()))?;
    let (low, high) = points
        .iter()
        .fold((*first, *first), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
    let center = nalgebra::center(&low, &high);
    let radius = points
        .iter()
        .map(|p| (p - center).norm())
        .fold(0.0, f64::max);
    if radius > 0.0 && radius.is_finite() && center.iter().all(|c| c.is_finite()) {
        Ok((center, radius))
    } else if radius == 0.0 {
        Err(Error::Mesh("the mesh has no extent".into()))
    } else {
        let reach = points
            .iter()
            .flat_map(|p| p.iter())
            .fold(0.0f64, |m, c| m.max(c.abs()));
        Err(Error::Mesh(format!(
            "the mesh is too large to draw: its coordinates reach {reach:e}, so distances \
             between its points are not finite numbers; scale it down"
        )))
    }
}

/// The unit direction from the scene to the eye and an up vector for an orbit view.
fn orbit(azimuth: f64, elevation: f64) -> Result<(Vector, Vector)> {
    if !(azimuth.is_finite() && elevation.is_finite()) {
        return Err(Error::Argument(format!(
            "the view angles (`view`) must be finite, got azimuth {azimuth}, elevation {elevation}"
        )));
    }
    let (az, el) = (azimuth.to_radians(), elevation.to_radians());
    let direction = Vector::new(el.cos() * az.sin(), el.sin(), el.cos() * az.cos());
    // The derivative of the direction by elevation: orthogonal to it even at the poles.
    let up = Vector::new(-el.sin() * az.sin(), el.cos(), -el.sin() * az.cos());
    Ok((direction, up))
}

/// The unit direction from the target to the eye and the given up vector.
fn look_at(eye: &Point, target: &Point, up: &Vector) -> Result<(Vector, Vector)> {
    let finite = eye
        .iter()
        .chain(target.iter())
        .chain(up.iter())
        .all(|v| v.is_finite());
    let direction = eye - target;
    let distance = direction.norm();
    if !finite || distance == 0.0 || !distance.is_finite() {
        return Err(Error::Argument(format!(
            "`camera` needs finite coordinates and an eye apart from the target, at a distance a \
             double can hold; got eye {:?}, target {:?}",
            eye.coords.as_slice(),
            target.coords.as_slice()
        )));
    }
    let direction = direction / distance;
    let up_length = up.norm();
    if !(up_length > 0.0 && up_length.is_finite()) {
        return Err(Error::Argument(format!(
            "the up vector of `camera` {:?} needs a length that is positive and finite",
            up.as_slice()
        )));
    }
    if up.cross(&direction).norm() <= 1e-9 * up_length {
        return Err(Error::Argument(format!(
            "the up vector of `camera` {:?} must not be parallel to the viewing direction",
            up.as_slice()
        )));
    }
    Ok((direction, *up))
}
