//! Smooth parametric surfaces for the hard-surface robot ([`crate::hardsurface`]): patches of
//! ellipsoids, barrel tubes and tori (open shells with boundary loops), and closed capsules and
//! rounded boxes. Each is a grid of quads over `(u, v) ∈ [0, 1]²`, shared vertices within the part
//! and smooth normals (the area-weighted mean of the faces around a vertex), triangles
//! counter-clockwise seen from outside. Positions in metres, bind (model) space. Every angle goes
//! through [`crate::math`], so the bytes are the same on every platform.

use glam::Vec3;

use crate::math::sin_cos;
use crate::shapes::Shape;

/// A right-handed frame `(x, y, z)` whose `y` is the unit `axis`, fixed by the axis alone.
pub fn frame_about(axis: Vec3) -> (Vec3, Vec3, Vec3) {
    let y = axis.normalize();
    let helper = if y.z.abs() < 0.9 { Vec3::Z } else { Vec3::X };
    let z = helper.cross(y).normalize();
    (y.cross(z), y, z)
}

/// Which ends of the grid's rows are single points (a pole closes the surface there).
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Poles {
    None,
    First,
    Both,
}

/// A grid of `columns × rows` quads with points `point(u, v)`: `wrap` joins the last column to
/// the first (a full turn, so the column seam is no border); a pole makes row 0 (and with
/// [`Poles::Both`] row `rows` too) one vertex. `point` must be oriented so that `∂p/∂u × ∂p/∂v`
/// points outward. Normals are computed from the triangles.
pub fn grid(columns: u32, rows: u32, wrap: bool, poles: Poles, point: impl Fn(f32, f32) -> Vec3) -> Shape {
    let per_row = if wrap { columns } else { columns + 1 };
    let is_pole = |r: u32| (r == 0 && poles != Poles::None) || (r == rows && poles == Poles::Both);
    let mut shape = Shape::default();
    let mut row_start = Vec::with_capacity(rows as usize + 1);
    for r in 0..=rows {
        row_start.push(shape.positions.len() as u32);
        let v = r as f32 / rows as f32;
        if is_pole(r) {
            shape.positions.push(point(0.0, v));
        } else {
            shape.positions.extend((0..per_row).map(|c| point(c as f32 / columns as f32, v)));
        }
    }
    let at =
        |r: u32, c: u32| if is_pole(r) { row_start[r as usize] } else { row_start[r as usize] + c % per_row };
    for r in 0..rows {
        for c in 0..columns {
            let (a, b, cc, d) = (at(r, c), at(r, c + 1), at(r + 1, c + 1), at(r + 1, c));
            if !is_pole(r) {
                shape.indices.extend_from_slice(&[a, b, cc]);
            }
            if !is_pole(r + 1) {
                shape.indices.extend_from_slice(&[a, cc, d]);
            }
        }
    }
    shape.normals = smooth_normals(&shape.positions, &shape.indices);
    shape
}

/// Per vertex, the normalized sum of its triangles' cross products (area-weighted face normals).
pub fn smooth_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    let mut sums = vec![Vec3::ZERO; positions.len()];
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| positions[t[k] as usize]);
        let n = (b - a).cross(c - a);
        for &v in t {
            sums[v as usize] += n;
        }
    }
    sums.into_iter().map(|n| n.normalize()).collect()
}

/// `columns × rows` for about `triangles` triangles on a patch `aspect` times as long around (u)
/// as along (v): at least 3 columns and 1 row.
pub fn split(triangles: f32, aspect: f32) -> (u32, u32) {
    let columns = (0.5 * triangles * aspect).sqrt().round().max(3.0);
    let rows = (0.5 * triangles / columns).round().max(1.0);
    (columns as u32, rows as u32)
}

/// An angle range in turns: from `.0` to `.1` (a full turn is `(0, 1)`; `.1` may exceed 1).
pub type Turns = (f32, f32);

/// Whether `turns` is a whole turn (the grid wraps).
fn whole(turns: Turns) -> bool {
    turns.1 - turns.0 >= 1.0
}

fn angle(turns: Turns, t: f32) -> (f32, f32) {
    sin_cos(std::f32::consts::TAU * (turns.0 + (turns.1 - turns.0) * t))
}

/// A patch of the ellipsoid at `center` with axis `axis` (its `y`), radii `(rx, ry, rz)` along
/// the frame of [`frame_about`]: longitudes `around` (turns, from the frame's `x` towards its
/// `z`), latitudes `lat` (0 the pole at `+axis`, 1 the one at `−axis`). A latitude range from 0
/// closes the top with a pole; to 1, the bottom.
pub fn ellipsoid(
    center: Vec3,
    axis: Vec3,
    radii: Vec3,
    around: Turns,
    lat: (f32, f32),
    triangles: f32,
) -> Shape {
    let (x, y, z) = frame_about(axis);
    let mean_r = (radii.x + radii.z) * 0.5;
    let aspect =
        (around.1 - around.0) * 2.0 * mean_r / ((lat.1 - lat.0) * 0.5 * (radii.y + mean_r)).max(1e-3);
    let (columns, rows) = split(triangles, aspect);
    let poles = match (lat.0 == 0.0, lat.1 == 1.0) {
        (true, true) => Poles::Both,
        (true, false) => Poles::First,
        (false, false) => Poles::None,
        (false, true) => panic!("a pole only at the bottom: flip the axis"),
    };
    grid(columns, rows, whole(around), poles, |u, v| {
        let (sp, cp) = angle(around, u);
        let (st, ct) = sin_cos(std::f32::consts::PI * (lat.0 + (lat.1 - lat.0) * v));
        center + x * (radii.x * st * cp) + y * (radii.y * ct) + z * (radii.z * st * sp)
    })
}

/// `sign(x)·|x|^e`, the superquadric's signed power.
fn signed_pow(x: f32, e: f32) -> f32 {
    libm::powf(x.abs(), e).copysign(x)
}

/// A closed rounded box: the superellipsoid at `center` with axis `axis`, half-extents `radii`
/// (as in [`ellipsoid`]) and exponent `e` (1 an ellipsoid; smaller is boxier).
pub fn rounded_box(center: Vec3, axis: Vec3, radii: Vec3, e: f32, triangles: f32) -> Shape {
    let (x, y, z) = frame_about(axis);
    let (columns, rows) = split(triangles, 2.0 * (radii.x + radii.z) / (radii.y + 0.5 * (radii.x + radii.z)));
    grid(columns, rows.max(2), true, Poles::Both, |u, v| {
        let (sp, cp) = sin_cos(std::f32::consts::TAU * u);
        let (st, ct) = sin_cos(std::f32::consts::PI * v);
        let (st, ct, sp, cp) = (signed_pow(st, e), signed_pow(ct, e), signed_pow(sp, e), signed_pow(cp, e));
        center + x * (radii.x * st * cp) + y * (radii.y * ct) + z * (radii.z * st * sp)
    })
}

/// A tube around `a → b` with elliptic radii `radii` (along the frame's `x` and `z`) that bulge by
/// `bulge` (a fraction) at mid-length and scale by `flare` from `a` to `b` (1 none), around
/// `around` (turns): a whole turn is an open sleeve (two boundary loops), less a curved plate.
pub fn tube(
    a: Vec3,
    b: Vec3,
    radii: (f32, f32),
    around: Turns,
    bulge: f32,
    flare: f32,
    triangles: f32,
) -> Shape {
    let (x, y, z) = frame_about(b - a);
    let length = a.distance(b);
    let aspect = (around.1 - around.0) * std::f32::consts::PI * (radii.0 + radii.1) / length;
    let (columns, rows) = split(triangles, aspect);
    grid(columns, rows, whole(around), Poles::None, |u, v| {
        let (sp, cp) = angle(around, u);
        let scale = (1.0 + bulge * sin_cos(std::f32::consts::PI * v).0) * (1.0 + (flare - 1.0) * v);
        // v runs from b down to a, so that ∂p/∂u × ∂p/∂v points outward.
        b - y * (length * v) + x * (radii.0 * scale * cp) + z * (radii.1 * scale * sp)
    })
}

/// A closed capsule from `a` to `b` of radius `radius` (hemispherical ends).
pub fn capsule(a: Vec3, b: Vec3, radius: f32, triangles: f32) -> Shape {
    let (x, y, z) = frame_about(b - a);
    let half = 0.5 * a.distance(b);
    let center = a.lerp(b, 0.5);
    let (columns, rows) = split(triangles, 2.0 * std::f32::consts::PI * radius / (2.0 * half + 2.0 * radius));
    // Rows spread over the profile's length: a quarter circle, the straight side, a quarter circle.
    let rows = rows.max(4);
    let cap = 0.5 * std::f32::consts::PI * radius;
    let total = 2.0 * cap + 2.0 * half;
    grid(columns, rows, true, Poles::Both, |u, v| {
        let s = v * total;
        let (along, ring) = if s < cap {
            let (st, ct) = sin_cos(s / radius);
            (half + radius * ct, radius * st)
        } else if s > total - cap {
            let (st, ct) = sin_cos((total - s) / radius);
            (-half - radius * ct, radius * st)
        } else {
            (half - (s - cap), radius)
        };
        let (sp, cp) = sin_cos(std::f32::consts::TAU * u);
        center + y * along + x * (ring * cp) + z * (ring * sp)
    })
}

/// A patch of the torus around `axis` at `center`: major radius `major`, tube radius `minor`,
/// `around` the axis (turns from the frame's `x` towards `z`) and `section` around the tube
/// (turns, 0 the outermost line, ¼ towards `+axis`).
pub fn torus(
    center: Vec3,
    axis: Vec3,
    (major, minor): (f32, f32),
    around: Turns,
    section: Turns,
    triangles: f32,
) -> Shape {
    let (x, y, z) = frame_about(axis);
    let aspect = (around.1 - around.0) * major / ((section.1 - section.0) * minor).max(1e-4);
    let (columns, rows) = split(triangles, aspect);
    grid(columns, rows, whole(around), Poles::None, |u, v| {
        let (sp, cp) = angle(around, u);
        // The section runs backwards, so that ∂p/∂u × ∂p/∂v points out of the tube.
        let (ss, cs) = angle((section.1, section.0), v);
        let ring = major + minor * cs;
        center + x * (ring * cp) + z * (ring * sp) + y * (minor * ss)
    })
}
