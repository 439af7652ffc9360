//! Mechanical energy from a result's object signals, shared by the tests that check its
//! conservation (`multibody.rs`, `loops.rs`).

use modia3d::prelude::*;

/// A solid whose centre of mass is at its object origin: (object name, mass [kg], inertia about
/// the centre of mass in the object frame [kg·m²]).
pub type Part<'a> = (&'a str, f64, Matrix3<f64>);

/// Kinetic + potential energy [J] of `parts` at every output point, gravity `g` resolved in
/// world [m/s²] (potential `−m g·r`).
pub fn energy(res: &SimulationResult, parts: &[Part], g: Vector3<f64>) -> Vec<f64> {
    let mut e = vec![0.0; res.time().len()];
    for (name, m, inertia) in parts {
        let r = res.signal(&format!("{name}.r_abs")).unwrap();
        let v = res.signal(&format!("{name}.v_abs")).unwrap();
        let w = res.signal(&format!("{name}.w_abs")).unwrap();
        let rot = res.signal(&format!("{name}.R_abs")).unwrap();
        for (k, ek) in e.iter_mut().enumerate() {
            let rm = Matrix3::from_row_slice(rot.at(k).unwrap());
            let wv = Vector3::from_column_slice(w.at(k).unwrap());
            let vv = Vector3::from_column_slice(v.at(k).unwrap());
            let rv = Vector3::from_column_slice(r.at(k).unwrap());
            let i_world = rm * inertia * rm.transpose();
            *ek += -m * g.dot(&rv) + 0.5 * m * vv.norm_squared() + 0.5 * wv.dot(&(i_world * wv));
        }
    }
    e
}
