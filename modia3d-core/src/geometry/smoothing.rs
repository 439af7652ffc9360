//! Smoothing of non-smooth shapes (geometry stage; touches nothing else).
//!
//! A box, cylinder, cone, beam or convex hull with smoothing radius `r_s > 0` is replaced by
//! `core ⊕ ball(r_s)`, the core being the shape shrunk by `r_s` (every face moved inwards by
//! `r_s`). Flat faces keep their place, so the outer dimensions stay as given; edges and vertices
//! become round, and the outward normal is unique and continuous (the idea of parry's
//! `RoundShape`, and of Modia3D's `smoothingRadius`).

use super::error::GeometryError;
use super::shapes::Shape;
use nalgebra::{Matrix3, Point3, Vector3};

/// Default smoothing radius \[m\] (Modia3D's default: 1 mm).
pub const DEFAULT_SMOOTHING_RADIUS: f64 = 1e-3;

/// Upper bound of the smoothing radius as a fraction of the smallest dimension of a shape.
pub const MAX_SMOOTHING_FRACTION: f64 = 0.1;

/// The smoothing radius actually used for `shape` when `requested` \[m\] is asked for:
/// 0 for shapes that are smooth already (sphere, capsule, ellipsoid), otherwise
/// `min(requested, 0.1 · smallest dimension)` \[m\]. For a cone the top diameter is not counted
/// (a pointed cone has none); for a convex hull the smallest dimension is twice the smallest
/// distance from the vertex centroid to a face (`hull_inner_width`).
pub fn effective_smoothing_radius(shape: &Shape, requested: f64) -> Result<f64, GeometryError> {
    if !(requested.is_finite() && requested >= 0.0) {
        return Err(GeometryError::InvalidSmoothingRadius(requested));
    }
    // The kind's bound (`geometry/kinds/<kind>.rs`, `smoothed_width`).
    let Some(smallest) = shape.smoothed_width()? else {
        return Ok(0.0);
    };
    Ok(requested.min(MAX_SMOOTHING_FRACTION * smallest))
}

/// Outward face planes `(n, h)` (`n·x ≤ h` inside, `n` unit) of the convex hull of `points`,
/// coplanar triangles merged, and the centroid of the hull vertices \[m\].
type Planes = Vec<(Vector3<f64>, f64)>;

fn hull_planes(points: &[Point3<f64>]) -> Result<(Planes, Point3<f64>), GeometryError> {
    if points.len() < 4
        || points
            .iter()
            .any(|p| !p.coords.iter().all(|x| x.is_finite()))
    {
        return Err(GeometryError::DegenerateHull);
    }
    let (verts, tris) = parry3d_f64::transformation::convex_hull(points);
    if verts.len() < 4 || tris.len() < 4 {
        return Err(GeometryError::DegenerateHull);
    }
    let c = Point3::from(verts.iter().map(|v| v.coords).sum::<Vector3<f64>>() / verts.len() as f64);
    let size = verts.iter().map(|v| (v - c).norm()).fold(0.0, f64::max);
    let mut planes: Vec<(Vector3<f64>, f64)> = Vec::with_capacity(tris.len());
    for t in &tris {
        let (a, b, d) = (
            verts[t[0] as usize],
            verts[t[1] as usize],
            verts[t[2] as usize],
        );
        let Some(mut n) = (b - a).cross(&(d - a)).try_normalize(1e-14 * size * size) else {
            continue; // a sliver triangle: its plane is given by its neighbours
        };
        if n.dot(&(a - c)) < 0.0 {
            n = -n;
        }
        let h = n.dot(&a.coords);
        let dup = planes
            .iter()
            .any(|(m, g)| (m - n).norm() < 1e-9 && (g - h).abs() < 1e-9 * size);
        if !dup {
            planes.push((n, h));
        }
    }
    let inner = planes
        .iter()
        .map(|(n, h)| h - n.dot(&c.coords))
        .fold(f64::INFINITY, f64::min);
    if planes.len() < 4 || inner.is_nan() || inner <= 1e-12 * size {
        return Err(GeometryError::DegenerateHull);
    }
    Ok((planes, c))
}

/// Twice the smallest distance from the centroid of the hull vertices to a face of the convex
/// hull of `points` \[m\] (a lower bound of the hull's smallest width through its centroid).
pub fn hull_inner_width(points: &[Point3<f64>]) -> Result<f64, GeometryError> {
    let (planes, c) = hull_planes(points)?;
    Ok(2.0
        * planes
            .iter()
            .map(|(n, h)| h - n.dot(&c.coords))
            .fold(f64::INFINITY, f64::min))
}

/// The vertices of the convex hull of `points` with every face moved inwards by `r` \[m\]
/// (`r` must be below half of [`hull_inner_width`]). With `r = 0` these are the hull vertices.
///
/// Method: the shrunk polytope is the intersection of the half-spaces `n_i·x ≤ h_i − r`. By
/// polar duality about the centroid `c`, its vertices correspond to the facets of the convex hull
/// of the dual points `n_i / (h_i − r − n_i·c)`; each dual facet (triangle i, j, k) gives the
/// primal vertex solving the 3×3 system of its three planes. Cost O(F log F) for F faces.
pub fn shrink_convex_hull(
    points: &[Point3<f64>],
    r: f64,
) -> Result<Vec<Point3<f64>>, GeometryError> {
    let (planes, c) = hull_planes(points)?;
    if r == 0.0 {
        let (verts, _) = parry3d_f64::transformation::convex_hull(points);
        return Ok(verts);
    }
    let shrunk: Vec<(Vector3<f64>, f64)> = planes
        .iter()
        .map(|(n, h)| (*n, h - r - n.dot(&c.coords)))
        .collect();
    if shrunk.iter().any(|(_, h)| h.is_nan() || *h <= 0.0) {
        return Err(GeometryError::DegenerateHull);
    }
    let dual: Vec<Point3<f64>> = shrunk.iter().map(|(n, h)| Point3::from(n / *h)).collect();
    let (dverts, dtris) = parry3d_f64::transformation::convex_hull(&dual);
    // Map the dual hull's vertices back to plane indices (the hull may reorder them).
    let index_of = |p: &Point3<f64>| {
        dual.iter()
            .enumerate()
            .min_by(|(_, a), (_, b)| (*a - p).norm().total_cmp(&(*b - p).norm()))
            .map(|(i, _)| i)
            .unwrap_or(0)
    };
    let idx: Vec<usize> = dverts.iter().map(index_of).collect();
    let size = points.iter().map(|p| (p - c).norm()).fold(0.0, f64::max);
    let mut out: Vec<Point3<f64>> = Vec::new();
    for t in &dtris {
        let (i, j, k) = (idx[t[0] as usize], idx[t[1] as usize], idx[t[2] as usize]);
        let m = Matrix3::from_rows(&[
            shrunk[i].0.transpose(),
            shrunk[j].0.transpose(),
            shrunk[k].0.transpose(),
        ]);
        let rhs = Vector3::new(shrunk[i].1, shrunk[j].1, shrunk[k].1);
        let Some(x) = m.lu().solve(&rhs) else {
            continue;
        };
        let p = c + x;
        // Keep only points inside all shrunk planes (guards against near-singular systems).
        let inside = shrunk.iter().all(|(n, h)| n.dot(&x) <= h + 1e-9 * size);
        if inside && out.iter().all(|q| (q - p).norm() > 1e-12 * size) {
            out.push(p);
        }
    }
    if out.is_empty() {
        return Err(GeometryError::DegenerateHull);
    }
    Ok(out)
}
